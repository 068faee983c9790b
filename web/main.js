// Page glue: checks for WebGPU, loads the wasm build of relief, and wires the controls and
// the shareable URL to it. All drawing is relief's own (Rust, through wgpu): no WebGPU here
// beyond the availability check.

const $ = (sel) => document.querySelector(sel);

function noWebGPU(reason) {
  $("#no-webgpu-reason").textContent = reason;
  $("#no-webgpu").hidden = false;
  $("#relief").hidden = true;
  document.body.dataset.error = "no-webgpu";
}

function parseQuery(q) {
  const out = {};
  for (const [k, v] of new URLSearchParams(q)) out[k.replace(/-/g, "_")] = v;
  return out;
}

function showValues(values) {
  for (const input of document.querySelectorAll("#controls [data-key]")) {
    const v = values[input.dataset.key];
    if (v === undefined) continue;
    if (input.type === "checkbox") input.checked = v === "1" || v === "true";
    else input.value = v;
    const out = input.parentElement.querySelector("output");
    if (out) out.textContent = v;
  }
}

async function main() {
  if (!("gpu" in navigator)) {
    return noWebGPU("This browser has no navigator.gpu.");
  }
  let adapter = null;
  try {
    adapter = await navigator.gpu.requestAdapter();
  } catch (e) {
    return noWebGPU(`navigator.gpu.requestAdapter() failed: ${e}`);
  }
  if (!adapter) {
    return noWebGPU("navigator.gpu.requestAdapter() returned null: WebGPU is disabled or no GPU adapter is available.");
  }

  let relief;
  try {
    relief = await import("./pkg/relief.js");
    await relief.default();
  } catch (e) {
    $("#error").textContent = `could not load relief's wasm (build it with web/build.sh): ${e}`;
    document.body.dataset.error = "load";
    return;
  }

  showValues(parseQuery(relief.default_query()));
  $("#controls").hidden = false;
  relief.start("relief", location.search);

  // relief reports the options it runs with; the URL and the controls follow them.
  window.addEventListener("relief-options", () => {
    const query = document.body.dataset.query || "";
    showValues(parseQuery(query));
    history.replaceState(null, "", `${location.pathname}?${query}`);
  });

  for (const input of document.querySelectorAll("#controls [data-key]")) {
    const send = () => {
      const value = input.type === "checkbox" ? (input.checked ? "1" : "0") : input.value;
      relief.set_param(input.dataset.key, value);
    };
    input.addEventListener(input.type === "range" ? "input" : "change", send);
  }
  $("#reseed").addEventListener("click", () => {
    const seed = (Math.random() * 4294967295) >>> 0;
    relief.set_param("seed", String(seed));
  });
  $("#copy-link").addEventListener("click", async () => {
    try {
      await navigator.clipboard.writeText(location.href);
      $("#copy-link").textContent = "link copied";
    } catch {
      prompt("Copy this link:", location.href);
    }
  });
}

main().catch((e) => {
  $("#error").textContent = String(e);
  document.body.dataset.error = "exception";
  console.error(e);
});
