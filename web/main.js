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

// A slider spans the comfortable part of a parameter's range (relief's table); the URL may
// set any value of the whole range. A value in force outside the slider, or between its steps,
// widens it or refines its step, so the slider shows what is drawn (a slider left at its end
// would change the terrain at the first nudge).
function showOnSlider(input, v) {
  const x = Number(v);
  if (!Number.isFinite(x)) return;
  if (x < Number(input.min)) input.min = v;
  if (x > Number(input.max)) input.max = v;
  input.value = v;
  if (Number(input.value) === x) return;
  // Whole numbers keep whole steps (an integer parameter refuses fractions).
  input.step = Number.isInteger(x) && Number.isInteger(Number(input.step)) ? "1" : "any";
  input.value = v;
  if (Number(input.value) !== x) { input.step = "any"; input.value = v; }
}

function showValues(values) {
  for (const input of document.querySelectorAll("#params [data-key]")) {
    const key = input.dataset.key;
    const v = values[key];
    // relief leaves out of its query the keys the method does not read (the blog's pipeline
    // has its own seed; the ray casters no texture size or grid): their controls rest. The
    // method itself is left out where it is the mesh.
    if (key !== "method") {
      input.disabled = v === undefined;
      input.parentElement.classList.toggle("unread", v === undefined);
      input.title = v === undefined ? "the method drawn does not read this" : "";
    }
    if (v === undefined) continue;
    if (input.type === "checkbox") input.checked = v === "1" || v === "true";
    else if (input.type === "range") showOnSlider(input, v);
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
    const values = parseQuery(query);
    showValues(values);
    if (!$("#controls").classList.contains("stopped")) $("#reseed").disabled = values.seed === undefined;
    history.replaceState(null, "", `${location.pathname}?${query}`);
  });
  window.addEventListener("relief-stopped", () => {
    $("#controls").classList.add("stopped");
    $("#params").disabled = true;
    for (const b of document.querySelectorAll(".buttons button")) b.disabled = true;
  });
  relief.start("relief", location.search);

  // The panel is a form for its layout and keyboard behaviour only: it never submits (Enter in
  // a field of a form submits it, which reloaded the page at a bare "/?" with every setting lost).
  $("#controls").addEventListener("submit", (e) => e.preventDefault());
  for (const input of document.querySelectorAll("#params [data-key]")) {
    const send = () => {
      const value = input.type === "checkbox" ? (input.checked ? "1" : "0") : input.value;
      relief.set_param(input.dataset.key, value);
    };
    input.addEventListener(input.type === "range" ? "input" : "change", send);
    // Enter in a field commits its value, as leaving it does.
    if (input.tagName === "INPUT" && input.type !== "checkbox") {
      input.addEventListener("keydown", (e) => {
        if (e.key !== "Enter") return;
        e.preventDefault();
        send();
      });
    }
  }
  $("#switch-world").addEventListener("click", () => {
    location.search = endless ? "" : "?world=endless";
  });
  $("#reseed").addEventListener("click", () => {
    const seed = (Math.random() * 4294967295) >>> 0;
    relief.set_param("seed", String(seed));
  });
  let copied = 0;
  $("#copy-link").addEventListener("click", async () => {
    try {
      await navigator.clipboard.writeText(location.href);
      $("#copy-link").textContent = "link copied";
      // Back to its name, so a second copy (of a changed URL) says so again.
      clearTimeout(copied);
      copied = setTimeout(() => { $("#copy-link").textContent = "copy link"; }, 2000);
    } catch {
      prompt("Copy this link:", location.href);
    }
  });
  // The panel folds to its toggle, so a small screen sees the terrain.
  $("#toggle-panel").addEventListener("click", () => {
    const folded = $("#controls").classList.toggle("folded");
    $("#toggle-panel").textContent = folded ? "controls" : "hide";
    $("#toggle-panel").setAttribute("aria-expanded", String(!folded));
    $("#toggle-panel").title = folded ? "show the controls" : "hide the controls";
  });
}

main().catch((e) => {
  $("#fatal").textContent = String(e);
  $("#fatal").hidden = false;
  document.body.dataset.error = "exception";
  console.error(e);
});
