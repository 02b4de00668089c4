// End-to-end tests of the web studio in headless Chromium (docs/web.md): the site that
// `scripts/web.sh build` made (SITE, default target/web) is served on a free port and driven
// with Playwright. Chromium runs without a GPU: WebGL2 on SwiftShader.
//
//   cd tests/web && npm ci && npm test
//
// CHROMIUM names the browser (default /usr/bin/chromium); SHOTS, a folder for the screenshots
// the tests take (default tests/web/out).
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import http from "node:http";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";

const here = path.dirname(fileURLToPath(import.meta.url));
const root = path.resolve(here, "../..");
const site = path.resolve(root, process.env.SITE ?? "target/web");
const shots = path.resolve(root, process.env.SHOTS ?? path.join(here, "out"));
const executablePath = process.env.CHROMIUM ?? "/usr/bin/chromium";
// SwiftShader draws the preview on the CPU, and the module compiles without a JIT cache.
const SLOW = 180_000;
const VIEWPORT = { width: 1280, height: 800 };

const types = {
  ".html": "text/html", ".js": "text/javascript", ".wasm": "application/wasm",
  ".toml": "text/plain",
};
let server, base, context, page, userData;
const errors = [];

function serve() {
  return new Promise((resolve) => {
    const s = http.createServer((req, res) => {
      const url = new URL(req.url, "http://localhost");
      const file = path.join(site, url.pathname === "/" ? "index.html" : url.pathname);
      if (!file.startsWith(site) || !fs.existsSync(file)) {
        res.writeHead(404).end();
        return;
      }
      res.writeHead(200, { "content-type": types[path.extname(file)] ?? "application/octet-stream" });
      fs.createReadStream(file).pipe(res);
    });
    s.listen(0, "127.0.0.1", () => resolve(s));
  });
}

/** Statistics of a PNG (a screenshot), computed by the browser: the mean and spread of its
 * grey levels, and how many of its pixels differ by more than 24 levels from `other`'s. */
async function compare(png, other) {
  const decode = async (buffer) => `data:image/png;base64,${buffer.toString("base64")}`;
  return page.evaluate(async ([a, b]) => {
    const pixels = async (src) => {
      const img = new Image();
      img.src = src;
      await img.decode();
      const c = new OffscreenCanvas(img.width, img.height);
      const g = c.getContext("2d");
      g.drawImage(img, 0, 0);
      return g.getImageData(0, 0, img.width, img.height).data;
    };
    const p = await pixels(a);
    const q = b ? await pixels(b) : null;
    let sum = 0, sum2 = 0, changed = 0;
    const n = p.length / 4;
    for (let i = 0; i < p.length; i += 4) {
      const grey = (p[i] + p[i + 1] + p[i + 2]) / 3;
      sum += grey;
      sum2 += grey * grey;
      if (q && Math.abs(p[i] - q[i]) + Math.abs(p[i + 1] - q[i + 1]) + Math.abs(p[i + 2] - q[i + 2]) > 24) {
        changed += 1;
      }
    }
    const mean = sum / n;
    return { mean, spread: Math.sqrt(Math.max(0, sum2 / n - mean * mean)), changed: changed / n };
  }, [await decode(png), other ? await decode(other) : null]);
}

/** A screenshot of part of the page (x, y, width, height in CSS pixels), also saved as NAME.png. */
async function shot(name, clip) {
  const png = await page.screenshot({ clip, path: path.join(shots, `${name}.png`) });
  return png;
}

// Where the studio's parts are in a 1280×800 window (egui lays them out the same every time):
// the left panel (design and layout), the middle (3D view, tiling, render) and its tab row.
const LEFT = { x: 0, y: 50, width: 295, height: 720 };
const MIDDLE = { x: 308, y: 104, width: 596, height: 656 };
const FULL = { x: 0, y: 0, ...VIEWPORT };
// Widgets clicked: the signature field, the tabs, and in the render tab the width field and
// the Render button.
const SIGNATURE = { x: 140, y: 86 };
const VIEW_TAB = { x: 338, y: 68 };
const TILING_TAB = { x: 400, y: 68 };
// The "Restore" button of the window that offers unsaved work after a reload.
const RESTORE = { x: 53, y: 100 };
const RENDER_TAB = { x: 458, y: 68 };
const LISTEN_TAB = { x: 517, y: 68 };
// The listen tab's Listen button.
const LISTEN_BUTTON = { x: 333, y: 91 };
// The strip of the echogram beside it that holds its title.
const ECHOGRAM_TITLE = { x: 600, y: 84, width: 240, height: 14 };
const RENDER_WIDTH = { x: 410, y: 91 };
const RENDER_BUTTON = { x: 872, y: 91 };
// The studio's File menu, and its Open… and Save As… items.
const FILE_MENU = { x: 24, y: 36 };
const FILE_OPEN = { x: 40, y: 84 };
const FILE_SAVE_AS = { x: 48, y: 156 };

/** Clicks at `at`, holding the button down a little: a press and release within one frame of
 * a busy page (a render taking its rounds) can be missed. */
async function click(at) {
  await page.mouse.click(at.x, at.y, { delay: 120 });
}

/** Waits until `n` more frames have been drawn (a few animation frames). */
async function frames(n = 10) {
  await page.evaluate((k) => new Promise((resolve) => {
    const step = (left) => (left === 0 ? resolve() : requestAnimationFrame(() => step(left - 1)));
    step(k);
  }), n);
}

/** Waits until the middle of the window stops changing (the preview or a render settled). */
async function settled(clip, timeout = SLOW) {
  const start = Date.now();
  let last = await page.screenshot({ clip });
  for (;;) {
    await page.waitForTimeout(1500);
    const next = await page.screenshot({ clip });
    if ((await compare(next, last)).changed < 0.001 || Date.now() - start > timeout) return next;
    last = next;
  }
}

before(async () => {
  assert.ok(fs.existsSync(path.join(site, "index.html")), `no site at ${site}: run scripts/web.sh build`);
  fs.mkdirSync(shots, { recursive: true });
  server = await serve();
  base = `http://127.0.0.1:${server.address().port}/`;
  userData = fs.mkdtempSync(path.join(os.tmpdir(), "orbifold-chromium-"));
  context = await chromium.launchPersistentContext(userData, {
    executablePath,
    headless: true,
    viewport: VIEWPORT,
    acceptDownloads: true,
    args: ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
      "--disable-component-update", "--disable-sync", "--no-first-run",
      // The test listens without a person's gesture on the page.
      "--autoplay-policy=no-user-gesture-required"],
  });
  // Every buffer of sound the page hands Web Audio, counted, with its loudest sample (the listen
  // tab plays through cpal's Web Audio host, one buffer after another).
  await context.addInitScript(() => {
    window.__sound = { buffers: 0, peak: 0 };
    const start = AudioBufferSourceNode.prototype.start;
    AudioBufferSourceNode.prototype.start = function (...args) {
      const buffer = this.buffer;
      if (buffer) {
        window.__sound.buffers += 1;
        for (let c = 0; c < buffer.numberOfChannels; c++) {
          for (const v of buffer.getChannelData(c)) {
            window.__sound.peak = Math.max(window.__sound.peak, Math.abs(v));
          }
        }
      }
      return start.apply(this, args);
    };
  });
  page = context.pages()[0] ?? await context.newPage();
  page.on("console", (m) => { if (m.type() === "error") errors.push(m.text()); });
  page.on("pageerror", (e) => errors.push(String(e)));
  await page.goto(base);
  await page.waitForSelector("#loading", { state: "detached", timeout: SLOW });
  await frames(20);
}, { timeout: SLOW });

after(async () => {
  await context?.close();
  server?.close();
  if (userData) fs.rmSync(userData, { recursive: true, force: true });
});

test("the page loads without console errors and the canvas is not blank", { timeout: SLOW }, async () => {
  const whole = await settled(MIDDLE);
  await shot("start", FULL);
  assert.deepEqual(errors, [], "console errors");
  const middle = await compare(whole);
  assert.ok(middle.spread > 10, `the 3D view is blank: ${JSON.stringify(middle)}`);
  const left = await compare(await shot("start-left", LEFT));
  assert.ok(left.spread > 10, `the design panel is blank: ${JSON.stringify(left)}`);
  assert.match(await page.title(), /untitled — orbifold studio/);
});

test("typing a signature changes the layout and the 3D view", { timeout: SLOW }, async () => {
  const layoutBefore = await page.screenshot({ clip: LEFT });
  const viewBefore = await settled(MIDDLE);
  await click(SIGNATURE);
  await page.keyboard.press("Control+A");
  await page.keyboard.type("*333");
  await page.keyboard.press("Enter");
  await frames(10);
  const viewAfter = await settled(MIDDLE);
  const layoutAfter = await shot("signature-left", LEFT);
  await shot("signature", FULL);
  const layout = await compare(layoutAfter, layoutBefore);
  const view = await compare(viewAfter, viewBefore);
  assert.ok(layout.changed > 0.02, `the layout did not change: ${JSON.stringify(layout)}`);
  assert.ok(view.changed > 0.05, `the 3D view did not change: ${JSON.stringify(view)}`);
  assert.ok(view.spread > 10 && (await compare(viewAfter)).spread > 10, "the new 3D view is blank");
  // Unsaved work goes to the browser's storage, offered again after a crash.
  const kept = await page.evaluate(() => localStorage.getItem("orbifold-studio/recovery"));
  assert.match(kept ?? "", /signature = "\*333"/);
  assert.match(await page.title(), /untitled • — orbifold studio/);
  assert.deepEqual(errors, [], "console errors");
});

test("walking with W moves the 3D view, the tiling tab draws the cover", { timeout: SLOW }, async () => {
  const standing = await settled(MIDDLE);
  // Keys walk while the pointer is over the view.
  await page.mouse.move(MIDDLE.x + MIDDLE.width / 2, MIDDLE.y + MIDDLE.height / 2);
  await page.keyboard.down("w");
  await page.waitForTimeout(1500);
  await page.keyboard.up("w");
  const walked = await settled(MIDDLE);
  await shot("walked", FULL);
  const moved = await compare(walked, standing);
  assert.ok(moved.changed > 0.05, `the view did not move: ${JSON.stringify(moved)}`);
  await click(TILING_TAB);
  const tiling = await settled(MIDDLE);
  await shot("tiling", FULL);
  const drawn = await compare(tiling, walked);
  assert.ok(drawn.changed > 0.1, `the tiling tab did not open: ${JSON.stringify(drawn)}`);
  assert.ok((await compare(tiling)).spread > 10, "the tiling is blank");
  assert.deepEqual(errors, [], "console errors");
});

test("the render tab produces a picture", { timeout: SLOW }, async () => {
  await click(RENDER_TAB);
  await frames(5);
  // A small picture, so that a round of samples on one core in SwiftShader's company is quick.
  await click(RENDER_WIDTH);
  await page.keyboard.press("Control+A");
  await page.keyboard.type("200");
  await page.keyboard.press("Enter");
  await frames(5);
  const empty = await page.screenshot({ clip: MIDDLE });
  await click(RENDER_BUTTON);
  // The picture is shown after the first round of samples, then refined: wait for it.
  const start = Date.now();
  let result, picture;
  do {
    await page.waitForTimeout(2000);
    picture = await page.screenshot({ clip: MIDDLE });
    result = await compare(picture, empty);
  } while (result.changed < 0.1 && Date.now() - start < SLOW - 20_000);
  await shot("render", FULL);
  assert.ok(result.changed > 0.1, `no picture appeared: ${JSON.stringify(result)}`);
  assert.ok((await compare(picture)).spread > 10, "the picture is blank");
  assert.deepEqual(errors, [], "console errors");
});

test("the listen tab plays the room's echoes through Web Audio", { timeout: SLOW }, async () => {
  // The render of the test before takes its rounds between frames until it is done; a click
  // while frames are that slow can be missed.
  await settled(MIDDLE);
  await click(LISTEN_TAB);
  await frames(5);
  const before = await page.screenshot({ clip: MIDDLE });
  await click(LISTEN_BUTTON);
  // The echoes are found on the page's thread, then played buffer by buffer.
  const start = Date.now();
  let sound;
  do {
    await page.waitForTimeout(1000);
    sound = await page.evaluate(() => window.__sound);
  } while (sound.peak < 0.01 && Date.now() - start < SLOW - 30_000);
  await frames(10);
  const after = await shot("listen", FULL);
  assert.ok(sound.buffers > 0 && sound.peak >= 0.01, `nothing was played: ${JSON.stringify(sound)}`);
  assert.ok(sound.peak <= 1, `the sound clips: ${JSON.stringify(sound)}`);
  // The echogram is drawn beside the button.
  const echogram = await compare(await page.screenshot({ clip: MIDDLE }), before);
  assert.ok(echogram.changed > 0.02, `no echogram appeared: ${JSON.stringify(echogram)}`);
  // Its title is drawn (a page has no system fonts: the picture's text uses egui's font).
  const title = await compare(await page.screenshot({ clip: ECHOGRAM_TITLE }));
  assert.ok(title.spread > 8, `the echogram has no title: ${JSON.stringify(title)}`);
  assert.ok((await compare(after)).spread > 10, "the page is blank");
  assert.deepEqual(errors, [], "console errors");
});

test("a scene file opened through the file input loads", { timeout: SLOW }, async () => {
  // Back to the 3D view from the render tab: the middle changes from the picture to the view.
  const rendered = await page.screenshot({ clip: MIDDLE });
  let before;
  for (let attempt = 0; attempt < 3; attempt += 1) {
    await click(VIEW_TAB);
    before = await settled(MIDDLE);
    if ((await compare(before, rendered)).changed > 0.05) break;
  }
  assert.ok((await compare(before, rendered)).changed > 0.05, "the 3D view tab did not open");
  const leftBefore = await page.screenshot({ clip: LEFT });
  await page.setInputFiles("#open-scene", path.join(root, "examples/scenes/fig-8.8-2233.toml"));
  await page.waitForFunction(() => document.title.startsWith("fig-8.8-2233.toml"), null, { timeout: SLOW });
  const after = await settled(MIDDLE);
  await shot("opened", FULL);
  assert.ok((await compare(await page.screenshot({ clip: LEFT }), leftBefore)).changed > 0.02,
    "the design panel did not change");
  assert.ok((await compare(after, before)).changed > 0.05, "the 3D view did not change");
  // A saved (just opened) document leaves nothing to recover.
  assert.equal(await page.evaluate(() => localStorage.getItem("orbifold-studio/recovery")), null);
  assert.deepEqual(errors, [], "console errors");
});

/** Drops a file called `name` with `bytes` (a string, or base64 when `encoded`) on the page,
 * as a person dragging it from their files would. */
function drop(name, bytes, encoded = false) {
  return page.evaluate(([n, b, e]) => {
    const data = new DataTransfer();
    const content = e ? Uint8Array.from(atob(b), (c) => c.charCodeAt(0)) : b;
    data.items.add(new File([content], n, { type: "application/octet-stream" }));
    const canvas = document.getElementById("studio");
    for (const type of ["dragenter", "dragover", "drop"]) {
      canvas.dispatchEvent(new DragEvent(type, { dataTransfer: data, bubbles: true, cancelable: true }));
    }
  }, [name, bytes, encoded]);
}

/** A closed box 0.8 wide and 1.6 tall, as OBJ: the mesh the tests drop. */
const BOX_OBJ = [
  "v -0.4 0 -0.4", "v 0.4 0 -0.4", "v 0.4 0 0.4", "v -0.4 0 0.4",
  "v -0.4 1.6 -0.4", "v 0.4 1.6 -0.4", "v 0.4 1.6 0.4", "v -0.4 1.6 0.4",
  "f 1 2 3 4", "f 8 7 6 5", "f 1 5 6 2", "f 2 6 7 3", "f 3 7 8 4", "f 4 8 5 1", "",
].join("\n");

/** A 2×2 PNG, all red. */
const RED_PNG = "iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAIAAAD91JpzAAAAEElEQVR42mP4z8AARAwQCgAf7gP9Y167WwAAAABJRU5ErkJggg==";

/** The unsaved work the page keeps, as text. */
const recovery = () => page.evaluate(() => localStorage.getItem("orbifold-studio/recovery"));

test("a dropped scene opens, a dropped mesh becomes an object, a PNG goes on the floor", { timeout: SLOW }, async () => {
  const scene = fs.readFileSync(path.join(root, "examples/scenes/fig-1.2-444.toml"), "utf8");
  await drop("fig-1.2-444.toml", scene);
  await page.waitForFunction(() => document.title.startsWith("fig-1.2-444.toml"), null, { timeout: SLOW });
  const before = await settled(MIDDLE);
  // A file the studio does not take changes nothing.
  await drop("notes.txt", "not a scene");
  await frames(20);
  assert.match(await page.title(), /^fig-1\.2-444\.toml — orbifold studio$/);
  // A mesh is added at the room's centre, where the camera looks, with its mirror images.
  await drop("box.obj", BOX_OBJ);
  await page.waitForFunction(() => document.title.includes("•"), null, { timeout: SLOW });
  const withBox = await settled(MIDDLE);
  await shot("dropped-mesh", FULL);
  const added = await compare(withBox, before);
  assert.ok(added.changed > 0.01, `the 3D view did not change: ${JSON.stringify(added)}`);
  assert.match(await recovery() ?? "", /mesh = "box\.obj"/);
  // The mesh is kept with the unsaved work, for a reload.
  const kept = await page.evaluate(() => localStorage.getItem("orbifold-studio/file/box.obj"));
  assert.equal(Buffer.from(kept ?? "", "base64").toString(), BOX_OBJ);
  // An image goes on the surface the room panel names for dropped images (the floor).
  await drop("red.png", RED_PNG, true);
  await page.waitForFunction(() => /path = "red\.png"/.test(localStorage.getItem("orbifold-studio/recovery") ?? ""), null, { timeout: SLOW });
  const floored = await settled(MIDDLE);
  await shot("dropped-texture", FULL);
  assert.ok((await compare(floored, withBox)).changed > 0.01, "the floor did not change");
  assert.ok(await page.evaluate(() => localStorage.getItem("orbifold-studio/file/red.png") !== null));
  assert.deepEqual(errors, [], "console errors");
});

test("unsaved work survives a reload of the page and is restored", { timeout: SLOW }, async () => {
  await click(SIGNATURE);
  await page.keyboard.press("Control+A");
  await page.keyboard.type("*2224");
  await page.keyboard.press("Enter");
  await page.waitForFunction(() => document.title.includes("•"), null, { timeout: SLOW });
  const kept = await page.evaluate(() => localStorage.getItem("orbifold-studio/recovery"));
  assert.match(kept ?? "", /signature = "\*2224"/);
  // A reload is what a crash of the tab leaves: the work is offered back.
  await page.reload();
  await page.waitForSelector("#loading", { state: "detached", timeout: SLOW });
  await frames(20);
  assert.match(await page.title(), /^untitled — orbifold studio$/);
  const offered = await page.screenshot({ clip: LEFT });
  await shot("recovery", FULL);
  await click(RESTORE);
  await page.waitForFunction(() => document.title.startsWith("untitled •"), null, { timeout: SLOW });
  await frames(10);
  const restored = await page.screenshot({ clip: LEFT });
  assert.ok((await compare(restored, offered)).changed > 0.02, "the design panel did not change");
  // The dropped mesh and image came back with it (the scene names them; nothing is missing):
  // the 3D view draws (a mesh it could not read would leave an error in its place).
  assert.ok((await compare(await settled(MIDDLE))).spread > 10, "the restored 3D view is blank");
  const work = await recovery();
  assert.match(work ?? "", /mesh = "box\.obj"/);
  assert.match(work ?? "", /path = "red\.png"/);
  assert.ok(await page.evaluate(() => localStorage.getItem("orbifold-studio/file/box.obj") !== null));
  assert.deepEqual(errors, [], "console errors");
});

test("the File menu opens the browser's file picker and saves as a download", { timeout: SLOW }, async () => {
  const before = await settled(MIDDLE);
  // The menu, then its item: a click on a busy page (SwiftShader drawing the preview on the
  // CPU) can be missed, so the two clicks are tried again, up to three times.
  let chooser;
  for (let attempt = 0; attempt < 3 && !chooser; attempt += 1) {
    await click(FILE_MENU);
    await frames(5);
    await shot("file-menu", FULL);
    [chooser] = await Promise.all([
      page.waitForEvent("filechooser", { timeout: 20_000 }).catch(() => undefined),
      click(FILE_OPEN),
    ]);
  }
  assert.ok(chooser, "File → Open… did not open the file picker");
  assert.equal(await chooser.element().getAttribute("accept"), ".toml");
  await chooser.setFiles(path.join(root, "examples/scenes/fig-8.8-2233.toml"));
  await page.waitForFunction(() => document.title.startsWith("fig-8.8-2233.toml"), null, { timeout: SLOW });
  const after = await settled(MIDDLE);
  assert.ok((await compare(after, before)).changed > 0.05, "the 3D view did not change");
  // Save As… hands the scene to the browser as a download, under the name it was opened as.
  await click(FILE_MENU);
  await frames(5);
  const [download] = await Promise.all([
    page.waitForEvent("download", { timeout: 30_000 }),
    click(FILE_SAVE_AS),
  ]);
  assert.equal(download.suggestedFilename(), "fig-8.8-2233.toml");
  const saved = fs.readFileSync(await download.path(), "utf8");
  assert.match(saved, /signature = "\*2233"/);
  assert.deepEqual(errors, [], "console errors");
});
