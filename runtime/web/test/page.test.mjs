// The built-in page in a real headless Chromium (Debian's, driven by playwright-core).
// 1. Offline: the bundled page draws a session fed to it (maps, trajectory, loops, scan).
// 2. Live: during a simulator run of `plugslam run --serve`, the trajectory grows; Pause pauses
//    the run; the editor edits a parameter, saves, and `plugslam validate` accepts the file; a
//    save outside the host's folder is refused. Screenshots are kept in build/test-artifacts/.
// Each part skips, saying why, where Chromium, the bundle or the host's server is missing.
import assert from "node:assert/strict";
import { spawn, spawnSync } from "node:child_process";
import { mkdirSync, mkdtempSync, rmSync, existsSync, readFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import test from "node:test";
import { syntheticSession } from "../bench/synthetic_session.mjs";
import { browserMissing, buildDir, launchChromium, serveStatic, sourceDir, webDir } from "./support.mjs";

const artifacts = join(buildDir, "test-artifacts");
const plugslam = join(buildDir, "bin", "plugslam");
const missing = browserMissing();

// The bundle served statically, pointed at a port nobody serves (the test feeds the messages);
// `errors` collects the page's uncaught errors.
async function offlinePage(browser, server) {
  const page = await browser.newPage({ viewport: { width: 1100, height: 700 } });
  const errors = [];
  page.on("pageerror", (e) => errors.push(String(e)));
  await page.goto(`${server.url}/?ws=ws://127.0.0.1:9`);
  await page.waitForFunction(() => window.plugslamView);
  return { page, errors };
}

test("the page draws a session fed to it", { skip: missing || false }, async () => {
  const server = await serveStatic(webDir);
  const browser = await launchChromium();
  try {
    const { page, errors } = await offlinePage(browser, server);
    const maps = 60, points = 200;
    await page.evaluate((msgs) => msgs.forEach(([t, m]) => window.plugslamView.ingest(t, m)),
      syntheticSession({ maps, points }));
    await page.waitForFunction((n) => window.plugslamView.counts().mapSourcePoints === n, maps * points);
    const c = await page.evaluate(() => window.plugslamView.counts());
    assert.equal(c.localMaps, maps);
    // Thinned to one point per screen pixel: fewer drawn, none invented.
    assert.ok(c.mapPoints > 0 && c.mapPoints <= maps * points, `${c.mapPoints} map points drawn`);
    assert.equal(c.trajectoryVertices, maps * 9 * 2, "9 segments of 10 poses per local map");
    assert.ok(c.loopVertices > 0, "loop closures drawn");
    assert.equal(c.scanPoints, 360);
    // The status panel shows the /status message.
    await page.waitForFunction(() => document.querySelector('[data-status="local_maps"]')?.textContent === "60");
    // Every camera image gets its own panel, in topic order (the right one arrives first here).
    const pixel = "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAAAAAA6fptVAAAACklEQVR4nGNgAAAAAgABSK+kcQAAAABJRU5ErkJggg==";
    await page.evaluate((data) => {
      for (const side of ["right", "left"])
        window.plugslamView.ingest(`/camera/${side}/image`, { timestamp: { sec: 1, nsec: 0 }, frame_id: `camera/${side}`, format: "png", data });
    }, pixel);
    await page.waitForFunction(() => document.querySelectorAll("#cameras figure img[src]").length === 2);
    assert.deepEqual(await page.evaluate(() => [...document.querySelectorAll("#cameras figure")].map((f) => f.dataset.topic)),
      ["/camera/left/image", "/camera/right/image"]);
    // Something is drawn where the robot is: without the metre grid, the canvas centre is not
    // all background colour.
    await page.evaluate(() => (window.plugslamView.view.grid.visible = false));
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    const drawn = await page.evaluate(() => {
      const canvas = document.getElementById("view");
      const gl = canvas.getContext("webgl2") || canvas.getContext("webgl");
      const px = new Uint8Array(4 * 64 * 64);
      gl.readPixels(canvas.width / 2 - 32, canvas.height / 2 - 32, 64, 64, gl.RGBA, gl.UNSIGNED_BYTE, px);
      let n = 0;
      for (let i = 0; i < px.length; i += 4) if (Math.abs(px[i] - 0xf4) > 8 || Math.abs(px[i + 2] - 0xf4) > 8) ++n;
      return n;
    });
    assert.ok(drawn > 50, `only ${drawn} drawn pixels around the robot`);
    mkdirSync(artifacts, { recursive: true });
    await page.screenshot({ path: join(artifacts, "page-offline.png") });

    // Zooming with the wheel keeps following the robot; panning hands the camera to the user.
    const box = await page.locator("#view").boundingBox();
    const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];
    await page.mouse.move(cx, cy);
    const zoom = await page.evaluate(() => window.plugslamView.view.camera.zoom);
    await page.mouse.wheel(0, -300);
    await page.waitForFunction((z) => window.plugslamView.view.camera.zoom !== z, zoom);
    assert.equal(await page.evaluate(() => window.plugslamView.view.follow), true, "a wheel zoom stopped following");
    assert.equal(await page.isChecked("#follow"), true);
    await page.mouse.down();
    await page.mouse.move(cx + 80, cy + 40, { steps: 5 });
    await page.mouse.up();
    assert.equal(await page.evaluate(() => window.plugslamView.view.follow), false, "a pan did not hand over the camera");
    assert.equal(await page.isChecked("#follow"), false);
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
    server.close();
  }
});

// A local map's point must land where the host's frames put it: the cloud's own pose applied in
// its map's frame, the map's origin (on /tf/maps, as the host sends it) applied once, the same
// composition Foxglove and Lichtblick make. The point (1, 0) of a cloud posed at (1, 0) in map/7,
// whose origin is (10, 5) turned by 90 degrees, is at world (10, 7); it must be drawn there on
// screen, and nowhere else.
test("a local map's point lands at its world position and screen pixel", { skip: missing || false }, async () => {
  const server = await serveStatic(webDir);
  const browser = await launchChromium();
  try {
    const { page, errors } = await offlinePage(browser, server);
    const q = (yaw) => ({ x: 0, y: 0, z: Math.sin(yaw / 2), w: Math.cos(yaw / 2) });
    const xyz = { point_stride: 12, fields: [{ name: "x", offset: 0, type: 7 }, { name: "y", offset: 4, type: 7 }, { name: "z", offset: 8, type: 7 }] };
    const b64 = (values) => Buffer.from(new Float32Array(values).buffer).toString("base64");
    const msgs = [
      ["/tf/maps", { transforms: [{ timestamp: { sec: 1, nsec: 0 }, parent_frame_id: "world", child_frame_id: "map/7", translation: { x: 10, y: 5, z: 0 }, rotation: q(Math.PI / 2) }] }],
      ["/map/front", { timestamp: { sec: 1, nsec: 0 }, frame_id: "map/7", pose: { position: { x: 1, y: 0, z: 0 }, orientation: q(0) }, ...xyz, data: b64([1, 0, 0]) }],
      // The robot 3 m to the right of the point: followed, it is the centre of the view.
      ["/pose", { timestamp: { sec: 1, nsec: 0 }, frame_id: "world", pose: { position: { x: 13, y: 7, z: 0 }, orientation: q(0) } }],
    ];
    await page.evaluate((m) => {
      for (const [topic, msg] of m) window.plugslamView.ingest(topic, msg, topic === "/tf/maps" ? "foxglove.FrameTransforms" : "");
      window.plugslamView.view.grid.visible = false;
    }, msgs);
    await page.waitForFunction(() => window.plugslamView.counts().mapPoints === 1);
    const world = await page.evaluate(() => [...window.plugslamView.view.positions("map")]);
    assert.ok(Math.abs(world[0] - 10) < 1e-5 && Math.abs(world[1] - 7) < 1e-5 && Math.abs(world[2]) < 1e-5, `drawn at ${world}`);
    await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
    // The pixel, from the orthographic top view's own numbers (not three.js's projection): the
    // camera looks down at the robot, (right - left) / zoom metres across the canvas.
    const found = await page.evaluate(() => {
      const { camera } = window.plugslamView.view;
      const canvas = document.getElementById("view");
      const w = canvas.width, h = canvas.height;
      const sx = (w * camera.zoom) / (camera.right - camera.left), sy = (h * camera.zoom) / (camera.top - camera.bottom);
      const expected = [w / 2 + (10 - camera.position.x) * sx, h / 2 - (7 - camera.position.y) * sy];
      const gl = canvas.getContext("webgl2") || canvas.getContext("webgl");
      const px = new Uint8Array(4 * w * h);
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
      const dark = [];  // the map's colour, 0x202020; the robot is green, the background 0xf4
      for (let y = 0; y < h; ++y)
        for (let x = 0; x < w; ++x) {
          const i = 4 * (y * w + x);
          if (px[i] < 0x40 && px[i + 1] < 0x40 && px[i + 2] < 0x40) dark.push([x, h - 1 - y]);
        }
      return { expected, dark };
    });
    assert.ok(found.dark.length > 0, "the map point is not drawn");
    // Within 2 pixels (the point is 2 px wide; pixel centres and rounding take the rest).
    for (const [x, y] of found.dark)
      assert.ok(Math.abs(x - found.expected[0]) <= 2 && Math.abs(y - found.expected[1]) <= 2,
        `a map pixel at (${x}, ${y}), the point belongs at (${found.expected})`);
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
    server.close();
  }
});

/** Resolves with the first match of `re` in the host's stdout; rejects when it exits first. */
function waitForOutput(host, re, timeout, log) {
  return new Promise((ok, fail) => {
    let out = "";
    const timer = setTimeout(() => fail(new Error(`no ${re} from the host within ${timeout} ms:\n${log()}`)), timeout);
    const onData = (d) => {
      out += d;
      const m = out.match(re);
      if (m) {
        clearTimeout(timer);
        host.stdout.off("data", onData);
        ok(m);
      }
    };
    host.stdout.on("data", onData);
    host.once("exit", (code) => {
      clearTimeout(timer);
      fail(new Error(`the host exited (${code}) before it served:\n${log()}`));
    });
  });
}

function serveMissing() {
  if (missing) return missing;
  if (!existsSync(plugslam)) return `no ${plugslam} (build first)`;
  const help = spawnSync(plugslam, ["run", "--help"], { encoding: "utf8" }).stdout || "";
  if (!help.includes("--serve")) return "this host has no `run --serve` (the viewer server)";
  return "";
}

// Every wait below is on a condition with a generous timeout, so neither a fast machine (the
// run is paced at the data's own speed, --rate 1: stage-3 lasts far longer than the test) nor a
// slow or busy one (plugins loading, SwiftShader drawing) decides the outcome.
test("live: the page follows a simulator run, pauses it, and edits its config", { skip: serveMissing() || false, timeout: 540000 }, async () => {
  const dir = mkdtempSync(join(tmpdir(), "plugslam-page-"));
  const host = spawn(plugslam, ["run", join(sourceDir, "configs", "sim2d_double_laser.yaml"), "-o", join(dir, "out"),
    "--serve", "127.0.0.1:0", "--rate", "1", "--set", "source.session=stage-3"], { cwd: dir, stdio: ["ignore", "pipe", "pipe"] });
  let log = "";
  host.stdout.on("data", (d) => (log += d));
  host.stderr.on("data", (d) => (log += d));
  const exited = new Promise((r) => host.once("exit", r));
  let browser;
  try {
    const [, url] = await waitForOutput(host, /serving ws:\/\/(127\.0\.0\.1:\d+)/, 120000, () => log);
    browser = await launchChromium();
    const page = await browser.newPage({ viewport: { width: 1200, height: 800 } });
    await page.goto(`http://${url}/`, { timeout: 60000 });
    await page.waitForFunction(() => !!window.plugslamView, null, { timeout: 60000 });
    const trail = () => window.plugslamView.counts().trajectoryVertices + window.plugslamView.session.robotTrack.length;
    await page.waitForFunction(() => window.plugslamView.session.robotTrack.length > 2, null, { timeout: 60000 });
    const first = await page.evaluate(`(${trail})()`);
    await page.waitForFunction(`(${trail})() > ${first}`, null, { timeout: 60000 });
    assert.equal((await page.evaluate(() => window.plugslamView.session.status.state)), "running", "the run ended before the test paused it");

    // Pause: the host says paused and the frame counter stops.
    await page.click("#pause");
    await page.waitForFunction(() => window.plugslamView.session.status.state === "paused", null, { timeout: 60000 });
    const f1 = await page.evaluate(() => window.plugslamView.session.status.frame);
    await page.waitForTimeout(800);
    const f2 = await page.evaluate(() => window.plugslamView.session.status.frame);
    assert.equal(f2, f1, "frames went on while paused");
    // The maps are drawn where the scan is: most points of the current scan lie on walls the local
    // maps already hold (0.2 m: twice the simulator's range noise plus the current map's lag of
    // up to 1 s of new wall; a map misplaced by its origin puts almost none there).
    const onMap = () => {
      const { view } = window.plugslamView;
      const map = view.positions("map"), scan = view.positions("scan");
      if (map.length === 0 || scan.length === 0) return 0;
      const cell = 0.2, key = (x, y) => `${Math.floor(x / cell)},${Math.floor(y / cell)}`, cells = new Set();
      for (let i = 0; i < map.length; i += 3) cells.add(key(map[i], map[i + 1]));
      let near = 0;
      for (let i = 0; i < scan.length; i += 3) {
        const x = scan[i], y = scan[i + 1];
        let hit = false;
        for (let dx = -1; dx <= 1 && !hit; ++dx)
          for (let dy = -1; dy <= 1 && !hit; ++dy) hit = cells.has(key(x + dx * cell, y + dy * cell));
        if (hit) ++near;
      }
      return near / (scan.length / 3);
    };
    const minOnMap = 0.5;
    await page.waitForFunction(`(${onMap})() >= ${minOnMap}`, null, { timeout: 30000 }).catch(() => {});
    const fraction = await page.evaluate(`(${onMap})()`);
    console.log(`scan points on the drawn map: ${(100 * fraction).toFixed(1)} %`);
    assert.ok(fraction >= minOnMap, `only ${(100 * fraction).toFixed(0)} % of the scan lies on the drawn map`);
    mkdirSync(artifacts, { recursive: true });
    await page.screenshot({ path: join(artifacts, "page-live.png") });

    // The editor: change the splitter's distance, save, validate with the CLI.
    await page.click('[data-tab="editor"]');
    await page.waitForSelector(".param-input", { timeout: 60000 });
    const input = page.locator('[data-param="config.pipeline.tracker.splitter.distance"]');
    await input.fill("1.5");
    await input.dispatchEvent("change");
    await page.fill("#editor-path", "edited/mine.yaml");
    await page.click("#editor-save");
    await page.waitForFunction(() => /saved/.test(document.getElementById("editor-result").textContent), null, { timeout: 60000 });
    const saved = join(dir, "edited", "mine.yaml");
    assert.ok(existsSync(saved), "the file was not written under the host's folder");
    assert.match(readFileSync(saved, "utf8"), /distance: 1\.5/);
    const v = spawnSync(plugslam, ["validate", saved], { encoding: "utf8" });
    assert.equal(v.status, 0, v.stdout + v.stderr);
    await page.screenshot({ path: join(artifacts, "page-editor.png") });

    // Outside the folder: refused, nothing written.
    await page.fill("#editor-path", "../escaped.yaml");
    await page.click("#editor-save");
    await page.waitForFunction(() => /not saved/.test(document.getElementById("editor-result").textContent), null, { timeout: 60000 });
    assert.match(await page.textContent("#editor-result"), /refused/);
    assert.ok(!existsSync(join(dir, "..", "escaped.yaml")));
  } finally {
    await browser?.close();
    host.kill("SIGINT");
    await exited;
    rmSync(dir, { recursive: true, force: true });
  }
});
