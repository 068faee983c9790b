// Browser test of the web page (index.html) in headless Chromium through Playwright:
//   1. the page renders the scene given in its URL; a screenshot of the canvas is written to
//      web/test-output/page.png for run.sh to compare with `relief render` (FLIP);
//   2. no console errors;
//   3. changing a control (the seed) re-bakes and changes the picture, and the URL it leaves
//      reproduces that picture in a fresh page; Enter in a field applies it, never reloads;
//   4. a URL with bad entries keeps the good ones and lists the bad ones on the page, a refused
//      control value snaps back, a paused page stops drawing and says it is idle, animated
//      offsets stay short in the URL, the buttons fit the panel, and every row of relief's
//      parameter table reaches the page through its URL; a slider shows a value in force beyond
//      its span; a key the method does not read is refused with a notice; "copy link" comes
//      back; the panel folds;
//   5. without --enable-unsafe-webgpu the page shows the no-WebGPU message, panel hidden;
//   6. with WebGPU that cannot present (no SwiftShader flags), the device is lost on the first
//      frame: the page says so, tries a new device once, then says it stopped;
//   7. the endless world (world=endless): its own controls, its camera in the URL, W flies.
// Usage: node web/test/page.mjs (from the repository root, after web/build.sh).

import { chromium } from "playwright-core";
import http from "node:http";
import fs from "node:fs";
import path from "node:path";

const root = process.cwd();
const out = path.join(root, "web/test-output");
fs.mkdirSync(out, { recursive: true });
const W = 256, H = 192;
// The scene shared with the native render in run.sh.
const SCENE = "seed=7&size=256&grid=128&paused=1";
// The endless world's view shared with the native render in run.sh.
const ENDLESS = "world=endless&seed=3&pixel_error=16&no_grass=1";

const types = { ".html": "text/html", ".js": "text/javascript", ".mjs": "text/javascript",
  ".css": "text/css", ".wasm": "application/wasm", ".png": "image/png" };
const server = http.createServer((req, res) => {
  const url = new URL(req.url, "http://x");
  const file = path.join(root, decodeURIComponent(url.pathname === "/" ? "/index.html" : url.pathname));
  if (!file.startsWith(root) || !fs.existsSync(file) || fs.statSync(file).isDirectory()) {
    res.writeHead(404).end();
    return;
  }
  res.writeHead(200, { "content-type": types[path.extname(file)] || "application/octet-stream" });
  fs.createReadStream(file).pipe(res);
});
await new Promise((r) => server.listen(0, "127.0.0.1", r));
const base = `http://127.0.0.1:${server.address().port}`;

const flags = ["--headless", "--no-sandbox", "--no-first-run", "--disable-background-networking",
  "--disable-component-update", "--disable-sync", "--disable-quic"];
// WebGPU itself needs only --enable-unsafe-webgpu here, but presenting to a canvas in headless
// Chromium without a GPU needs SwiftShader behind Vulkan and ANGLE: without these flags the
// canvas's swap-chain image cannot be created and the device is lost on the first frame.
const webgpu = ["--enable-unsafe-webgpu", "--enable-features=Vulkan", "--use-angle=vulkan",
  "--use-vulkan=swiftshader", "--enable-unsafe-swiftshader"];
let failures = 0, passes = 0;
const check = (ok, what) => {
  console.log(`${ok ? "ok" : "FAIL"} - ${what}`);
  if (ok) passes++; else failures++;
};

async function withBrowser(extra, fn) {
  const browser = await chromium.launch({
    executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
    args: [...flags, ...extra],
  });
  try {
    return await fn(browser);
  } finally {
    await browser.close();
  }
}

async function openPage(browser, url, errors) {
  const page = await browser.newPage({ viewport: { width: W, height: H }, deviceScaleFactor: 1 });
  page.on("console", (m) => { if (m.type() === "error") errors.push(m.text()); });
  page.on("pageerror", (e) => errors.push(String(e)));
  // The page's thread, watched from inside: the longest gap between 20 ms ticks is the longest
  // time it was held (by relief's frames, or anything else), and whether "baking" was shown.
  // A gap that begins and ends while the page waits for the GPU to build its pipelines
  // (<body data-preparing>, before the first frame) is kept apart: Chromium can hold the page's
  // thread while its GPU process compiles (seconds on SwiftShader), which no frame budget
  // changes.
  await page.addInitScript(() => {
    window.__longestHeldMs = 0;
    window.__preparingHeldMs = 0;
    window.__sawBaking = false;
    let last = performance.now();
    let wasPreparing = false;
    setInterval(() => {
      const now = performance.now();
      const preparing = !!document.body && document.body.dataset.preparing === "1";
      const key = wasPreparing && preparing ? "__preparingHeldMs" : "__longestHeldMs";
      window[key] = Math.max(window[key], now - last - 20);
      last = now;
      wasPreparing = preparing;
      const r = document.querySelector("#readout");
      if (r && /baking/.test(r.textContent)) window.__sawBaking = true;
    }, 20);
  });
  await page.goto(url);
  return page;
}

// Frames are counted on <body data-frames>; wait until `n` more have been drawn, or the page
// has gone idle (a paused page draws only when something changes, and says so at once).
async function waitFrames(page, n, timeout = 120000) {
  const now = Number(await page.evaluate(() => document.body.dataset.frames || 0));
  await page.waitForFunction(([t, n]) => {
    const f = Number(document.body.dataset.frames || 0);
    return f >= t + n || (f >= 1 && document.body.dataset.idle === "1");
  }, [now, n], { timeout });
}

// A screenshot of the canvas alone: the controls that float over it are hidden meanwhile.
async function shot(page, file, timeout = 120000) {
  const tag = await page.addStyleTag({ content: "#controls { display: none !important; }" });
  // Playwright waits for the canvas to hold still over two animation frames; with grass on
  // SwiftShader a frame takes seconds, so the wait gets as long as the frames' own (120 s).
  const png = await page.locator("#relief").screenshot({ timeout });
  await tag.evaluate((t) => t.remove());
  fs.writeFileSync(path.join(out, file), png);
  return png;
}

await withBrowser(webgpu, async (browser) => {
  const errors = [];
  const page = await openPage(browser, `${base}/index.html?${SCENE}`, errors);
  await page.waitForFunction(() => document.body.dataset.frames || document.body.dataset.error,
    null, { timeout: 120000 });
  const early = await page.evaluate(() => document.body.dataset.error || "");
  check(early === "", `page started (error: ${early || "none"})`);
  await waitFrames(page, 3);
  const first = await shot(page, "page.png");
  check(first.length > 1000, "screenshot of the canvas written to web/test-output/page.png");

  // Change the seed through its control, as a user would.
  await page.fill('input[data-key="seed"]', "8");
  await page.dispatchEvent('input[data-key="seed"]', "change");
  await page.waitForFunction(() => (document.body.dataset.query || "").includes("seed=8"), null,
    { timeout: 60000 });
  await waitFrames(page, 3);
  const second = await shot(page, "page-seed8.png");
  check(!first.equals(second), "changing the seed changes the picture");
  const url = page.url();
  check(url.includes("seed=8"), `the URL records the change (${url})`);

  // Enter in a field applies its value and never submits the panel's form (that reloaded the
  // page at a bare "/?", every setting lost): the page lives on and the URL keeps the scene.
  await page.evaluate(() => { window.__marker = "kept"; });
  await page.fill('input[data-key="seed"]', "9");
  await page.press('input[data-key="seed"]', "Enter");
  const entered = await page.waitForFunction(() => (document.body.dataset.query || "").includes("seed=9"),
    null, { timeout: 60000 }).then(() => true, () => false);
  // Long enough for a submission's navigation to have replaced the page.
  await page.waitForTimeout(1000);
  const marker = await page.evaluate(() => window.__marker).catch((e) => `gone (${e})`);
  const enterUrl = page.url();
  check(entered && marker === "kept" && ["seed=9", "size=256", "grid=128", "paused=1"].every((k) => enterUrl.includes(k)),
    `Enter in the seed field applies it without a reload (marker: ${marker}, URL ${enterUrl.slice(enterUrl.indexOf("?"), enterUrl.indexOf("?") + 60)}...)`);

  const errors2 = [];
  const again = await openPage(browser, url, errors2);
  await waitFrames(again, 3);
  const third = await shot(again, "page-seed8-reloaded.png");
  check(third.equals(second), "the URL reproduces the same picture");
  const all = [...errors, ...errors2];
  check(all.length === 0, `no console errors (${all.join(" | ") || "none"})`);
  fs.writeFileSync(path.join(out, "readout.txt"), await again.locator("#readout").innerText());

  // The method `blog` (the seed blog's pipeline, its own terrain) through the URL: drawn, named
  // by the readout and the control.
  const errors3 = [];
  const blog = await openPage(browser, `${base}/index.html?paused=1&method=blog`, errors3);
  await waitFrames(blog, 1);
  const named = await blog.waitForFunction(() => /^blog · /.test(document.querySelector("#readout").textContent),
    null, { timeout: 60000 }).then(() => true, () => false);
  const blogShot = await shot(blog, "page-blog.png");
  const bcontrol = await blog.evaluate(() => document.querySelector('[data-key="method"]')?.value);
  const bq = await blog.evaluate(() => document.body.dataset.query || "");
  check(named && !blogShot.equals(first) && bcontrol === "blog" && bq.includes("method=blog"),
    `method=blog draws the blog's pipeline, and the readout and control say so (${bcontrol})`);

  // The visibility method through the URL: the mesh rasterised, its samples shaded in compute
  // (run.sh compares the canvas with `relief render --method visibility` of the same scene).
  const vis = await openPage(browser, `${base}/index.html?${SCENE}&method=visibility`, errors3);
  await waitFrames(vis, 3);
  const visShot = await shot(vis, "page-visibility.png");
  const vcontrol = await vis.evaluate(() => document.querySelector('[data-key="method"]')?.value);
  const vq = await vis.evaluate(() => document.body.dataset.query || "");
  const verror = await vis.evaluate(() => document.body.dataset.error || "");
  check(verror === "" && visShot.length > 1000 && vcontrol === "visibility" && vq.includes("method=visibility"),
    `method=visibility draws, and the control and URL say so (${vcontrol}, error: ${verror || "none"})`);

  // The page's costs, on SwiftShader (Chromium's CPU WebGPU: not what a GPU's browser measures):
  // the wasm's size, the time from navigation to the first frame, the wasm's CPU time a frame.
  const anim = await openPage(browser, `${base}/index.html?seed=7&size=256&grid=128`, errors3);
  await anim.waitForFunction(() => document.body.dataset.cpu_ms, null, { timeout: 120000 });
  const firstMs = Number(await anim.evaluate(() => document.body.dataset.first_frame_ms));
  const cpuMs = Number(await anim.evaluate(() => document.body.dataset.cpu_ms));
  const wasmKib = fs.statSync(path.join(root, "web/pkg/relief_bg.wasm")).size / 1024;
  const metrics = `wasm_kib ${wasmKib.toFixed(0)}\nfirst_frame_ms ${firstMs}\ncpu_ms_per_frame ${cpuMs}\n`;
  fs.writeFileSync(path.join(out, "metrics.txt"), metrics);
  check(firstMs > 0 && cpuMs > 0 && /CPU [0-9.]+ ms\/frame/.test(await anim.locator("#readout").innerText()),
    `SwiftShader: wasm ${wasmKib.toFixed(0)} KiB, first frame at ${firstMs} ms, CPU ${cpuMs} ms a frame (in the readout)`);
  check(errors3.length === 0, `no console errors with the blog and the metrics (${errors3.join(" | ") || "none"})`);

  // Grass on the page: a meadow from 1.7 m (the GPU's rasteriser draws the blades: the page's
  // WebGPU has no 64-bit atomics for the compute raster). Drawn without error, its first frame
  // and the scatter's time a frame on SwiftShader (a CPU: not what a GPU's browser measures),
  // into metrics.txt and docs/results/grass.md. The blades show once the levels under them are
  // baked, which on SwiftShader takes minutes: the shot is the first frames' look.
  const errors4 = [];
  const meadow = "world=endless&eye=2740,1111.7,-3000&look_at=2770,1107.7,-2990&paused=1";
  const g = await openPage(browser, `${base}/index.html?${meadow}`, errors4);
  await waitFrames(g, 1);
  const grassFirstMs = Number(await g.evaluate(() => document.body.dataset.first_frame_ms));
  const scatter = await g.waitForFunction(
    () => (/grass ([0-9.]+) ms/.exec(document.querySelector("#readout").textContent) || [])[1],
    null, { timeout: 120000 }).then((h) => h.jsonValue(), () => "");
  // The shot is a picture, not a check: on SwiftShader a grass frame takes 15-20 s of the GPU
  // process, and the canvas rarely holds still for Playwright: it is given 30 s, not 120.
  await shot(g, "page-grass.png", 30000).catch((e) => console.log(`# no page-grass.png: ${String(e).split("\n")[0]}`));
  const gerror = await g.evaluate(() => document.body.dataset.error || "");
  const gq = await g.evaluate(() => document.body.dataset.query || "");
  fs.appendFileSync(path.join(out, "metrics.txt"),
    `grass_first_frame_ms ${grassFirstMs}\ngrass_scatter_ms ${scatter}\n`);
  check(grassFirstMs > 0 && scatter !== "" && gerror === "" && !gq.includes("no_grass=1")
    && errors4.length === 0,
    `grass on the page: drawn without error, first frame at ${grassFirstMs} ms, the scatter ${scatter} ms a frame on SwiftShader (error: ${gerror || errors4.join(" | ") || "none"})`);

  // The picture for the docs (not a check, and only when asked: PAGE_PICTURES=1): the whole
  // page, controls included.
  if (process.env.PAGE_PICTURES === "1") try {
    const full = await browser.newPage({ viewport: { width: 960, height: 600 }, deviceScaleFactor: 1 });
    await full.goto(`${base}/index.html?paused=1`);
    await waitFrames(full, 3);
    await full.waitForFunction(() => /fps|idle/.test(document.querySelector("#readout").textContent), null,
      { timeout: 60000 });
    await full.screenshot({ path: path.join(out, "page-full.png") });
  } catch (e) {
    console.log(`note: no full-page screenshot (${String(e).split("\n")[0]})`);
  }
});

await withBrowser(webgpu, async (browser) => {
  // Clouds on the page (off by default): the endless world with the default layer at coverage
  // 0.5, drawn without error; its first frame on SwiftShader (the clouds' pipelines built and
  // every pixel of their image marched on a CPU: not what a GPU's browser measures) into
  // metrics.txt and docs/results/clouds.md, and a shot of it (a picture, not a check).
  const errors5 = [];
  const cloudy = "world=endless&seed=3&pixel_error=16&no_grass=1&cloud_coverage=0.5&paused=1";
  const c = await openPage(browser, `${base}/index.html?${cloudy}`, errors5);
  // SwiftShader builds the clouds' march and marches them on a CPU (13 s here, alone in its browser).
  await waitFrames(c, 1, 300000);
  const cloudFirstMs = Number(await c.evaluate(() => document.body.dataset.first_frame_ms));
  await shot(c, "page-clouds.png", 30000).catch((e) => console.log(`# no page-clouds.png: ${String(e).split("\n")[0]}`));
  const cerror = await c.evaluate(() => document.body.dataset.error || "");
  const cq = await c.evaluate(() => document.body.dataset.query || "");
  fs.appendFileSync(path.join(out, "metrics.txt"), `clouds_first_frame_ms ${cloudFirstMs}\n`);
  check(cloudFirstMs > 0 && cerror === "" && cq.includes("cloud_coverage=0.5") && errors5.length === 0,
    `clouds on the page: drawn without error, first frame at ${cloudFirstMs} ms on SwiftShader (error: ${cerror || errors5.join(" | ") || "none"})`);
});

await withBrowser(webgpu, async (browser) => {
  // The running day on the page (`day_length`, N): a day in 60 s from 9:00 in the endless
  // world; over 30 s of the page's clock the hour in the canvas's title (winit's alt
  // attribute) moves on and frames keep
  // coming, each relighting what its budget allows. The frame rate and the hours it ran on
  // SwiftShader (a CPU: not what a GPU's browser measures) go to metrics.txt and
  // docs/results/day.md.
  const errors6 = [];
  const d = await openPage(browser, `${base}/index.html?${ENDLESS}&time_of_day=9&day_length=60`, errors6);
  await waitFrames(d, 1, 300000);
  const hourOf = (t) => (t.match(/ at (\d\d):(\d\d)/) || []).slice(1).map(Number);
  const hhmm = (t) => (t.match(/ at (\d\d:\d\d)/) || [])[1];
  const read = () => d.evaluate(() => ({
    title: document.getElementById("relief")?.getAttribute("alt") || "", frames: Number(document.body.dataset.frames || 0), t: performance.now(),
  }));
  const a = await read();
  await d.waitForTimeout(30000);
  const b = await read();
  // Still coming once the arrival's bake and the history's settling frames are over (they
  // stopped after 22 frames when the redraw forgot the running day).
  await d.waitForTimeout(8000);
  const c = await read();
  const [h0, m0] = hourOf(a.title);
  const [h1, m1] = hourOf(b.title);
  const ran = ((h1 * 60 + m1) - (h0 * 60 + m0) + 1440) % 1440;
  const seconds = (b.t - a.t) / 1000;
  const fps = (b.frames - a.frames) / seconds;
  const derror = await d.evaluate(() => document.body.dataset.error || "");
  fs.appendFileSync(path.join(out, "metrics.txt"),
    `day_frames_a_second ${fps.toFixed(2)}\nday_minutes_in_30s ${ran}\n`);
  // 30 s of a 60 s day is 12 hours; the title shows the hour of the last frame drawn, and a
  // slower machine's frames may come seconds apart (two frames and half an hour at least).
  check(b.frames >= a.frames + 2 && c.frames > b.frames && ran >= 30 && ran <= 13 * 60 && derror === "" && errors6.length === 0,
    `a running day on the page: ${hhmm(a.title)} -> ${hhmm(b.title)} (${ran} minutes of the day) in ${seconds.toFixed(1)} s, ${fps.toFixed(2)} frames a second on SwiftShader, frames ${a.frames} -> ${b.frames} -> ${c.frames} 8 s on (error: ${derror || errors6.join(" | ") || "none"})`);
  await d.close();
});

await withBrowser(webgpu, async (browser) => {
  // The endless world: its own controls, the camera in the URL, and flying with the keys.
  const errors = [];
  const page = await openPage(browser, `${base}/index.html?${ENDLESS}`, errors);
  await page.waitForFunction(() => document.body.dataset.frames || document.body.dataset.error,
    null, { timeout: 120000 });
  const early = await page.evaluate(() => document.body.dataset.error || "");
  check(early === "", `the endless world started (error: ${early || "none"})`);
  // Arrival: the first frame comes at once, coarse, and refines frame by frame while the page
  // says "baking…"; the page's thread is never held for a whole bake (SwiftShader's times: a
  // CPU device, labelled so; they are not a GPU's).
  await page.waitForFunction(() => document.body.dataset.baked_ms, null, { timeout: 300000 });
  const arrival = await page.evaluate(() => ({
    first: Number(document.body.dataset.first_frame_ms),
    baked: Number(document.body.dataset.baked_ms),
    frames: Number(document.body.dataset.baked_frames),
    longest: Number(document.body.dataset.baked_longest_frame_ms),
    held: Math.round(window.__longestHeldMs),
    preparingHeld: Math.round(window.__preparingHeldMs),
    saw: window.__sawBaking,
    baking: document.body.dataset.baking,
  }));
  check(arrival.saw && arrival.frames > 2 && arrival.baking === "" && arrival.first < arrival.baked,
    `arrival on SwiftShader: first frame at ${arrival.first} ms, baked and lit at ${arrival.baked} ms over ${arrival.frames} frames (the longest ${arrival.longest} ms apart), "baking…" shown meanwhile`);
  check(arrival.held < Math.max(5000, arrival.baked / 4),
    `the page's thread held at most ${arrival.held} ms at a time while baking (${arrival.baked} ms in all; before the first frame, while the GPU built the pipelines, ${arrival.preparingHeld} ms)`);
  fs.appendFileSync(path.join(out, "metrics.txt"),
    `endless_first_frame_ms ${arrival.first}\nendless_baked_ms ${arrival.baked}\n` +
    `endless_held_ms ${arrival.held}\nendless_held_building_pipelines_ms ${arrival.preparingHeld}\n`);
  await waitFrames(page, 2);
  const before = await shot(page, "page-endless.png");
  const q0 = await page.evaluate(() => document.body.dataset.query || "");
  check(q0.startsWith("world=endless") && /eye=[-0-9.]+%2C/.test(q0) && q0.includes("seed=3"),
    `the endless world's URL holds its keys and camera (${q0.slice(0, 100)}...)`);
  const controls = await page.evaluate(() => ["peak_height", "pixel_error", "terrain", "size", "grid"]
    .map((k) => !!document.querySelector(`[data-key="${k}"]`)));
  check(controls.join() === "true,true,true,false,false",
    `the endless world's controls, not the tile's (${controls.join()})`);
  // pixel_error=16 lies beyond its slider's span (to 8): the slider and its output show 16.
  const pe = await page.inputValue('input[data-key="pixel_error"]');
  const peOut = await page.evaluate(() =>
    document.querySelector('input[data-key="pixel_error"]').parentElement.querySelector("output").textContent);
  check(pe === "16" && peOut === "16", `the pixel_error slider shows the 16 in force (slider ${pe}, output ${peOut})`);
  const f0 = Number(await page.evaluate(() => document.body.dataset.frames));
  await page.locator("#relief").focus();
  // Held for 1.5 s, and on until three frames are drawn (a frame flying on SwiftShader bakes
  // the levels it uncovers: 0.5-1 s of a CPU).
  await page.keyboard.down("w");
  await page.waitForTimeout(1500);
  await page.waitForFunction((f) => Number(document.body.dataset.frames) > f + 2, f0,
    { timeout: 60000 }).catch(() => {});
  await page.keyboard.up("w");
  const moved = await page.waitForFunction((q) => (document.body.dataset.query || "") !== q, q0,
    { timeout: 30000 }).then(() => true, () => false);
  await waitFrames(page, 1);
  const f1 = Number(await page.evaluate(() => document.body.dataset.frames));
  const after = await shot(page, "page-endless-flown.png");
  const q1 = await page.evaluate(() => document.body.dataset.query || "");
  const eye = (q) => (q.match(/eye=([^&]*)/) || [])[1];
  check(moved && f1 > f0 + 2 && !after.equals(before) && eye(q1) !== eye(q0),
    `holding W flies: ${f1 - f0} frames, eye ${eye(q0)} -> ${eye(q1)}`);
  await page.fill('input[data-key="seed"]', "4");
  await page.dispatchEvent('input[data-key="seed"]', "change");
  const reseeded = await page.waitForFunction(() => (document.body.dataset.query || "").includes("seed=4"),
    null, { timeout: 30000 }).then(() => true, () => false);
  check(reseeded, "a control of the endless world changes it");
  // Every row of the endless world's table reaches it through the URL, and has its control.
  const wrows = await page.evaluate(async () =>
    JSON.parse((await import("./web/pkg/relief.js")).world_params_table()));
  // Each page is closed once checked: a page left open goes on drawing (the wall's running
  // day redraws every frame) and starves the next of SwiftShader's GPU process.
  await page.close();
  // time_of_day sets the sun's rows (its own check follows): here it stays unset (-1).
  // The clouds stay off (coverage 0: SwiftShader would march them) and their top above the
  // base the slider's first step puts at 50 m.
  const walt = (r) => r.key === "method" ? "raymarch" : r.key === "time_of_day" ? "-1"
    : r.key === "cloud_coverage" ? "0" : r.key === "cloud_top" ? "6000"
    : r.control === "select" ? r.choices[0] === "eroded" ? r.choices[1] : r.choices[0]
    : r.key === "feature_size" ? "2048" : String(r.min + r.step);
  const wurl = `${base}/index.html?world=endless&` + wrows.map((r) => `${r.key}=${walt(r)}`).join("&");
  const wall = await openPage(browser, wurl, errors);
  await waitFrames(wall, 1);
  const wq = await wall.evaluate(() => document.body.dataset.query || "");
  const wmissing = wrows.filter((r) => !wq.split("&").includes(`${r.key}=${walt(r)}`)).map((r) => r.key);
  const wcontrols = wrows.filter((r) => r.control !== "none");
  const wpresent = await wall.evaluate((keys) => keys.filter((k) => document.querySelector(`[data-key="${k}"]`)).length,
    wcontrols.map((r) => r.key));
  check(wmissing.length === 0 && wpresent === wcontrols.length,
    `all ${wrows.length} endless-world rows set through the URL (missing: ${wmissing.join(",") || "none"}), ${wpresent} controls`);
  await wall.close();
  // The hour puts the sun where the day has it: the URL keeps the hour and the sun it sets.
  const dusk = await openPage(browser, `${base}/index.html?${ENDLESS}&time_of_day=19`, errors);
  await waitFrames(dusk, 1);
  const dq = await dusk.evaluate(() => document.body.dataset.query || "");
  const dslider = await dusk.evaluate(() => document.querySelector('[data-key="time_of_day"]')?.value);
  check(dq.includes("time_of_day=19") && !dq.includes("sun_azimuth=145&") && dslider === "19",
    `time_of_day=19 reaches the URL, moves the sun and its slider shows it (${dslider}; ${dq})`);
  await dusk.close();

  // A ray caster instead of the mesh (`method` in the URL and its control): run.sh compares
  // the canvas with `relief render --method raymarch` of the same view.
  const marched = await openPage(browser, `${base}/index.html?${ENDLESS}&method=raymarch`, errors);
  await waitFrames(marched, 2);
  const mq = await marched.evaluate(() => document.body.dataset.query || "");
  const mcontrol = await marched.evaluate(() => document.querySelector('[data-key="method"]')?.value);
  await shot(marched, "page-endless-raymarch.png");
  check(mq.includes("method=raymarch") && mcontrol === "raymarch",
    `the method reaches the URL and its control (${mcontrol})`);
  await marched.close();

  // The hybrid (the endless world's): the raised mesh rasterised, each sample refined to the
  // continuous surface in compute; run.sh compares the canvas with `relief render --method hybrid`.
  const hybrid = await openPage(browser, `${base}/index.html?${ENDLESS}&method=hybrid`, errors);
  await waitFrames(hybrid, 2);
  const hq = await hybrid.evaluate(() => document.body.dataset.query || "");
  const hcontrol = await hybrid.evaluate(() => document.querySelector('[data-key="method"]')?.value);
  const herror = await hybrid.evaluate(() => document.body.dataset.error || "");
  await shot(hybrid, "page-endless-hybrid.png");
  check(herror === "" && hq.includes("method=hybrid") && hcontrol === "hybrid",
    `method=hybrid draws the endless world, and the URL and control say so (${hcontrol}, error: ${herror || "none"})`);
  await hybrid.close();

  // On the path, the URL holds the camera mode and the time along it, and the time runs.
  const onPath = await openPage(browser, `${base}/index.html?${ENDLESS}&camera=path&time=5`, errors);
  await waitFrames(onPath, 3);
  const runs = await onPath.waitForFunction(() => {
    const m = (document.body.dataset.query || "").match(/camera=path&.*time=([0-9.]+)/);
    return m && Number(m[1]) > 5;
  }, null, { timeout: 60000 }).then(() => true, () => false);
  const qp = await onPath.evaluate(() => document.body.dataset.query || "");
  check(runs, `the path's camera and time reach the URL and the time runs (${qp.slice(qp.indexOf("camera="))})`);
  check(errors.length === 0, `no console errors in the endless world (${errors.join(" | ") || "none"})`);

  // The picture for the docs (not a check, and only when asked: PAGE_PICTURES=1; on SwiftShader
  // it can take minutes): the whole page in the endless world.
  if (process.env.PAGE_PICTURES === "1") try {
    const full = await browser.newPage({ viewport: { width: 960, height: 600 }, deviceScaleFactor: 1 });
    await full.goto(`${base}/index.html?world=endless&pixel_error=6`);
    await waitFrames(full, 2);
    await full.waitForFunction(() => /fps|idle/.test(document.querySelector("#readout").textContent), null,
      { timeout: 60000 });
    await full.screenshot({ path: path.join(out, "page-endless-full.png") });
  } catch (e) {
    console.log(`note: no full-page screenshot of the endless world (${String(e).split("\n")[0]})`);
  }
  // And the page with props, from 2 m among them (the props' landscape's camera).
  if (process.env.PAGE_PICTURES === "1") try {
    const full = await browser.newPage({ viewport: { width: 800, height: 500 }, deviceScaleFactor: 1 });
    await full.goto(`${base}/index.html?world=endless&props=1&no_grass=1&camera=fly` +
      "&eye=2740,1112,-3000&look_at=2710,1106,-3030&fov=50&pixel_error=6");
    await waitFrames(full, 2);
    // On SwiftShader the view bakes and lights for about ten minutes, each frame's march 9-16 s.
    await full.waitForFunction(() => !/baking/.test(document.querySelector("#readout").textContent), null,
      { timeout: 900000 });
    await full.screenshot({ path: path.join(out, "page-props-full.png"), timeout: 300000 });
  } catch (e) {
    console.log(`note: no full-page screenshot with props (${String(e).split("\n")[0]})`);
  }
});

await withBrowser(webgpu, async (browser) => {
  // Bad URL entries: the rest applies, the bad ones are listed with their reasons.
  const errors = [];
  const page = await openPage(browser,
    `${base}/index.html?seed=abc&octaves=999&grid=64&colour=red&paused=maybe&size=64&normals=analytic`, errors);
  await waitFrames(page, 1);
  const query = await page.evaluate(() => document.body.dataset.query || "");
  check(["grid=64", "size=64", "normals=analytic"].every((k) => query.includes(k)),
    `valid URL keys kept (${query.slice(0, 80)})`);
  const notice = await page.locator("#notice").innerText();
  check(["seed", "octaves", "colour", "paused"].every((k) => notice.includes(k))
    && notice.includes("speed") && notice.includes("abc") && await page.locator("#notice").isVisible(),
    `bad URL entries listed on the page: "${notice.slice(0, 160)}..."`);
  // Each entry names its key once.
  check(notice.includes("invalid seed: abc (allowed: ") && !/seed: invalid seed/.test(notice),
    `a refused entry reads once ("${notice.slice(notice.indexOf("invalid seed"), notice.indexOf("invalid seed") + 50)}")`);

  // A refused value snaps the control back to the value in force, and says why.
  await page.fill('input[data-key="seed"]', "99999999999");
  await page.dispatchEvent('input[data-key="seed"]', "change");
  await page.waitForFunction(() => document.querySelector("#error").textContent.includes("seed"), null,
    { timeout: 30000 });
  const seedField = await page.inputValue('input[data-key="seed"]');
  check(seedField === "7", `a refused seed snaps back to the seed in force (field: ${seedField})`);
  // The refusal stays readable while the terrain scrolls (the URL updates twice a second).
  await page.waitForTimeout(1500);
  const still = await page.locator("#error").innerText();
  check(still.includes("seed"), `the refusal is still on the page 1.5 s later ("${still.slice(0, 80)}")`);

  // The buttons fit inside the panel.
  const panel = await page.locator("#controls").boundingBox();
  let fits = true;
  for (const b of await page.locator(".buttons button").all()) {
    const r = await b.boundingBox();
    fits &&= r.x >= panel.x && r.x + r.width <= panel.x + panel.width + 0.5;
  }
  check(fits, "the buttons fit inside the panel");

  // "copy link" says "link copied", then comes back (a second copy says so again). Headless
  // Chromium copies once granted the clipboard; where it still refuses, the page prompts.
  await page.context().grantPermissions(["clipboard-read", "clipboard-write"], { origin: base });
  let prompted = false;
  page.on("dialog", (d) => { prompted = true; d.dismiss().catch(() => {}); });
  await page.bringToFront();
  await page.click("#copy-link");
  const copiedSaid = await page.waitForFunction(() => document.querySelector("#copy-link").textContent === "link copied",
    null, { timeout: 5000 }).then(() => true, () => false);
  await page.waitForTimeout(3000);
  const copyText = await page.locator("#copy-link").innerText();
  check(copiedSaid && copyText === "copy link",
    `"copy link" says "link copied" (${copiedSaid}${prompted ? ", but the page prompted" : ""}), then "${copyText}" 3 s later`);

  // The panel folds to its toggle (a small screen sees the terrain) and unfolds as it was.
  const open = await page.locator("#controls").boundingBox();
  await page.click("#toggle-panel");
  const folded = await page.locator("#controls").boundingBox();
  const paramsHidden = !(await page.locator("#params").isVisible()) && !(await page.locator("#copy-link").isVisible());
  await page.click("#toggle-panel");
  const unfolded = await page.locator("#controls").boundingBox();
  check(folded.height < 60 && folded.width < open.width && paramsHidden
    && Math.abs(unfolded.height - open.height) < 1 && await page.locator("#params").isVisible(),
    `the panel folds (${open.width.toFixed(0)}x${open.height.toFixed(0)} -> ${folded.width.toFixed(0)}x${folded.height.toFixed(0)}) and unfolds (${unfolded.width.toFixed(0)}x${unfolded.height.toFixed(0)})`);

  // Animated: offsets in the URL stay short decimals; paused: drawing stops and the readout says so.
  await waitFrames(page, 3);
  await page.evaluate(() => { document.querySelector('input[data-key="paused"]').click(); });
  await page.waitForFunction(() => /paused=1/.test(document.body.dataset.query || ""), null, { timeout: 30000 });
  const offset = new URLSearchParams(new URL(page.url()).search).get("offset") || "";
  check(/^[0-9.]{1,8},[0-9.]{1,8}$/.test(offset), `URL offset is short (${offset})`);
  await page.waitForFunction(() => document.body.dataset.idle === "1", null, { timeout: 30000 });
  const before = Number(await page.evaluate(() => document.body.dataset.frames));
  await page.waitForTimeout(1500);
  const after = Number(await page.evaluate(() => document.body.dataset.frames));
  const readout = await page.locator("#readout").innerText();
  check(after === before && /idle/.test(readout), `paused and untouched: no frames drawn (${before} -> ${after}), readout "${readout}"`);
  await page.fill('input[data-key="gain"]', "0.3");
  await page.dispatchEvent('input[data-key="gain"]', "input");
  const redrawn = await page.waitForFunction((b) => Number(document.body.dataset.frames) > b, after,
    { timeout: 60000 }).then(() => true, () => false);
  check(redrawn, "a control change draws again");
  const cleared = await page.waitForFunction(() => document.querySelector("#error").textContent === "", null,
    { timeout: 30000 }).then(() => true, () => false);
  check(cleared, "a change that took effect clears the earlier refusal");

  // Every row of the table reaches the page through its URL.
  const rows = await page.evaluate(async () => JSON.parse((await import("./web/pkg/relief.js")).params_table()));
  // The method row: the cheap ray caster (the reference takes minutes a frame on a CPU). It
  // does not read these keys (Method::unread_keys): they are refused with it, and said so
  // (the URL above sets them with the mesh).
  const unread = ["size", "grid", "normals"];
  const alt = (r) => r.key === "method" ? "raymarch" : r.control === "checkbox" ? "1"
    : r.control === "select" ? r.choices[r.choices.length - 1]
    : r.control === "none" ? "0.5%2C0.25" : String(r.min + r.step);
  const url = rows.map((r) => `${r.key}=${alt(r)}`).join("&");
  const all = await openPage(browser, `${base}/index.html?${url}`, errors);
  await waitFrames(all, 1);
  const q = await all.evaluate(() => document.body.dataset.query || "");
  const missing = rows.filter((r) => !unread.includes(r.key) && !q.split("&").includes(`${r.key}=${alt(r)}`))
    .map((r) => r.key);
  const controls = rows.filter((r) => r.control !== "none");
  const present = await all.evaluate((keys) => keys.filter((k) => document.querySelector(`[data-key="${k}"]`)).length,
    controls.map((r) => r.key));
  check(missing.length === 0 && present === controls.length,
    `all ${rows.length - unread.length} table rows the ray caster reads set through the URL (missing: ${missing.join(",") || "none"}), ${present} controls`);
  const allNotice = await all.locator("#notice").innerText();
  const unsaid = unread.filter((k) => !allNotice.includes(`${k} does not apply to method raymarch`)
    || q.split("&").some((e) => e.startsWith(`${k}=`)));
  check(unsaid.length === 0, `the keys the ray caster does not read are refused and said so (not: ${unsaid.join(",") || "none"})`);

  // A key the method does not read (the blog's pipeline bakes its own noise, seed and all) is
  // refused with a notice that says why, as `relief render --method blog --seed 3` refuses it;
  // the rest of the URL applies, and the seed's control rests.
  const blog = await openPage(browser, `${base}/index.html?method=blog&seed=3&height_scale=0.8&paused=1`, errors);
  await waitFrames(blog, 1);
  const bq = await blog.evaluate(() => document.body.dataset.query || "");
  const bnotice = await blog.locator("#notice").innerText();
  const seedRests = await blog.locator('input[data-key="seed"]').isDisabled();
  check(/seed does not apply to method blog: the blog's pipeline bakes its own noise/.test(bnotice)
    && await blog.locator("#notice").isVisible()
    && bq.includes("method=blog") && bq.includes("height_scale=0.8") && !/(^|&)seed=/.test(bq) && seedRests,
    `method=blog&seed=3: "${bnotice.slice(0, 120)}", URL ${bq.slice(0, 60)}, seed control disabled: ${seedRests}`);

  // A value in force beyond its slider's span (frequency to 16): the slider and its output
  // show it, so a nudge moves from the terrain drawn.
  const wide = await openPage(browser, `${base}/index.html?frequency=64&octaves=10&paused=1`, errors);
  await waitFrames(wide, 1);
  const wq = await wide.evaluate(() => document.body.dataset.query || "");
  const freq = await wide.inputValue('input[data-key="frequency"]');
  const freqOut = await wide.evaluate(() =>
    document.querySelector('input[data-key="frequency"]').parentElement.querySelector("output").textContent);
  const oct = await wide.inputValue('input[data-key="octaves"]');
  check(wq.includes("frequency=64") && freq === "64" && freqOut === "64" && oct === "10",
    `frequency=64&octaves=10: the slider shows ${freq}, its output ${freqOut}, octaves ${oct}`);
  check(errors.length === 0, `no console errors (${errors.join(" | ") || "none"})`);
});

await withBrowser([], async (browser) => {
  const errors = [];
  const page = await openPage(browser, `${base}/index.html`, errors);
  const box = page.locator("#no-webgpu");
  await box.waitFor({ state: "visible", timeout: 30000 });
  const text = await box.innerText();
  check(/WebGPU is not available/.test(text) && /requestAdapter|navigator\.gpu/.test(text),
    `without WebGPU the page says so: "${text.split("\n").filter((l) => l.trim()).slice(0, 2).join(" / ")}"`);
  check(errors.length === 0, `no uncaught errors without WebGPU (${errors.join(" | ") || "none"})`);
  check(!(await page.locator("#controls").isVisible()), "the controls panel stays hidden over the message");
  await page.screenshot({ path: path.join(out, "no-webgpu.png") });
});

// WebGPU that cannot present to a canvas (here: no SwiftShader flags): the device is lost on
// the first frame. The page must say so, try a new device once, then say it stopped.
await withBrowser(["--enable-unsafe-webgpu"], async (browser) => {
  const errors = [];
  const page = await openPage(browser, `${base}/index.html?paused=1&size=64`, errors);
  await page.waitForFunction(() => document.body.dataset.error, null, { timeout: 120000 });
  const said = await page.locator("#error").innerText();
  const readout = await page.locator("#readout").innerText();
  check(/lost/i.test(said) && /stopped/.test(said) && await page.locator("#fatal").isVisible(),
    `a lost device is shown on the page: "${said.slice(0, 150)}"`);
  check(!/fps/.test(readout), `the readout does not pretend to draw ("${readout}")`);
  await page.screenshot({ path: path.join(out, "device-lost.png") });
});

server.close();
console.log(`${passes} passed, ${failures} failed`);
process.exit(failures ? 1 : 0);
