// Page glue: checks for WebGPU, loads the wasm build of relief, builds the controls from
// relief's parameter table, and keeps the controls and the shareable URL in step with it. All
// drawing is relief's own (Rust, through wgpu): no WebGPU here beyond the availability check.

const $ = (sel) => document.querySelector(sel);

function noWebGPU(reason) {
  $("#no-webgpu-reason").textContent = reason;
  $("#no-webgpu").hidden = false;
  $("#controls").hidden = true;
  $("#relief").hidden = true;
  document.body.dataset.error = "no-webgpu";
}

function parseQuery(q) {
  const out = {};
  for (const [k, v] of new URLSearchParams(q)) out[k.replace(/-/g, "_")] = v;
  return out;
}

// One control per row of relief's table (key, doc, control, range, choices).
function buildControls(rows) {
  const box = $("#params");
  for (const row of rows) {
    if (row.control === "none") continue;
    const label = document.createElement("label");
    label.title = `${row.doc} (allowed: ${row.allowed})`;
    label.append(row.key.replace(/_/g, " "));
    let input;
    if (row.control === "select") {
      input = document.createElement("select");
      for (const c of row.choices) input.append(new Option(c, c));
    } else {
      input = document.createElement("input");
      input.type = { slider: "range", number: "number", checkbox: "checkbox" }[row.control];
      if (row.control !== "checkbox") {
        input.min = row.min; input.max = row.max; input.step = row.step;
      }
    }
    if (row.control === "checkbox") label.classList.add("checkbox");
    input.dataset.key = row.key;
    label.append(input);
    if (row.control === "slider") label.append(document.createElement("output"));
    box.append(label);
  }
}

function showValues(values) {
  for (const input of document.querySelectorAll("#params [data-key]")) {
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
    $("#fatal").textContent = `could not load relief's wasm (build it with web/build.sh): ${e}`;
    $("#fatal").hidden = false;
    document.body.dataset.error = "load";
    return;
  }

  // The endless world (world=endless in the URL) has its own parameters and a fly camera.
  const endless = new URLSearchParams(location.search).get("world") === "endless";
  buildControls(JSON.parse(endless ? relief.world_params_table() : relief.params_table()));
  showValues(parseQuery(endless ? relief.default_world_query() : relief.default_query()));
  $("#switch-world").textContent = endless ? "the tile" : "endless world";
  $("#switch-world").title = endless
    ? "back to the seed blog's tile, seen from outside"
    : "a landscape to the horizon: WASD or arrows fly, Q/E down and up, drag to look, wheel for speed, P follows a path";
  $("#relief").setAttribute("aria-label", endless
    ? "landscape view: WASD or arrows fly, Q and E go down and up, drag to look, wheel for speed, P follows a path"
    : "terrain view: drag to orbit, wheel or pinch to zoom");
  $("#hint").hidden = !endless;
  $("#controls").hidden = false;

  // relief reports the options in force; the URL and the controls follow them (a refused
  // value puts the control back to the value in force).
  window.addEventListener("relief-options", () => {
    const query = document.body.dataset.query || "";
    showValues(parseQuery(query));
    history.replaceState(null, "", `${location.pathname}?${query}`);
  });
  window.addEventListener("relief-stopped", () => {
    $("#controls").classList.add("stopped");
    $("#params").disabled = true;
    for (const b of document.querySelectorAll(".buttons button")) b.disabled = true;
  });
  relief.start("relief", location.search);

  for (const input of document.querySelectorAll("#params [data-key]")) {
    const send = () => {
      const value = input.type === "checkbox" ? (input.checked ? "1" : "0") : input.value;
      relief.set_param(input.dataset.key, value);
    };
    input.addEventListener(input.type === "range" ? "input" : "change", send);
  }
  $("#switch-world").addEventListener("click", () => {
    location.search = endless ? "" : "?world=endless";
  });
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
  $("#fatal").textContent = String(e);
  $("#fatal").hidden = false;
  document.body.dataset.error = "exception";
  console.error(e);
});
