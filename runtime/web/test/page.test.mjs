// The built-in page in a real headless Chromium (Debian's, driven by playwright-core).
// 1. Offline: the bundled page draws a session fed to it (maps, trajectory, loops, scan).
// 2. Live: during a simulator run of `plugslam run --serve`, the trajectory grows; Pause pauses
//    the run; the editor edits a parameter, saves, and `plugslam validate` accepts the file; a
//    save outside the host's folder is refused. Screenshots are kept in build/test-artifacts/.
// Each part skips, saying why, where Chromium, the bundle or the host's server is missing.
import assert from "node:assert/strict";
import { spawn, spawnSync } from "node:child_process";
import { mkdirSync, mkdtempSync, rmSync, existsSync, readFileSync } from "node:fs";
import { createServer } from "node:net";
import { tmpdir } from "node:os";
import { join } from "node:path";
import test from "node:test";
import { syntheticSession } from "../bench/synthetic_session.mjs";
import { browserMissing, buildDir, launchChromium, serveStatic, sourceDir, webDir } from "./support.mjs";

const artifacts = join(buildDir, "test-artifacts");
const plugslam = join(buildDir, "bin", "plugslam");
const missing = browserMissing();

test("the page draws a session fed to it", { skip: missing || false }, async () => {
  const server = await serveStatic(webDir);
  const browser = await launchChromium();
  try {
    const page = await browser.newPage({ viewport: { width: 1100, height: 700 } });
    const errors = [];
    page.on("pageerror", (e) => errors.push(String(e)));
    await page.goto(`${server.url}/?ws=ws://127.0.0.1:9`);
    await page.waitForFunction(() => window.plugslamView);
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
    assert.deepEqual(errors, []);
  } finally {
    await browser.close();
    server.close();
  }
});

function freePort() {
  return new Promise((ok) => {
    const s = createServer();
    s.listen(0, "127.0.0.1", () => {
      const port = s.address().port;
      s.close(() => ok(port));
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

test("live: the page follows a simulator run, pauses it, and edits its config", { skip: serveMissing() || false, timeout: 180000 }, async () => {
  const dir = mkdtempSync(join(tmpdir(), "plugslam-page-"));
  const port = await freePort();
  // The longest built-in session, so there is time to watch it.
  const host = spawn(plugslam, ["run", join(sourceDir, "configs", "default.yaml"), "-o", join(dir, "out"),
    "--serve", `127.0.0.1:${port}`, "--set", "source.session=stage-3"], { cwd: dir, stdio: ["ignore", "pipe", "pipe"] });
  let log = "";
  host.stdout.on("data", (d) => (log += d));
  host.stderr.on("data", (d) => (log += d));
  const browser = await launchChromium();
  try {
    const page = await browser.newPage({ viewport: { width: 1200, height: 800 } });
    let loaded = false;
    for (let i = 0; i < 100 && !loaded; ++i) {
      try {
        await page.goto(`http://127.0.0.1:${port}/`);
        loaded = await page.evaluate(() => !!window.plugslamView);
      } catch {
        await new Promise((r) => setTimeout(r, 100));
      }
    }
    assert.ok(loaded, `the page did not load from the host:\n${log}`);
    const vertices = () => page.evaluate(() => window.plugslamView.counts().trajectoryVertices + window.plugslamView.session.robotTrack.length);
    await page.waitForFunction(() => window.plugslamView.session.robotTrack.length > 2, null, { timeout: 30000 });
    const first = await vertices();
    await page.waitForTimeout(700);
    const second = await vertices();
    assert.ok(second > first, `the trajectory did not grow (${first} -> ${second})`);

    // Pause: the host says paused and the frame counter stops.
    await page.click("#pause");
    await page.waitForFunction(() => window.plugslamView.session.status.state === "paused", null, { timeout: 10000 });
    const f1 = await page.evaluate(() => window.plugslamView.session.status.frame);
    await page.waitForTimeout(800);
    const f2 = await page.evaluate(() => window.plugslamView.session.status.frame);
    assert.equal(f2, f1, "frames went on while paused");
    mkdirSync(artifacts, { recursive: true });
    await page.screenshot({ path: join(artifacts, "page-live.png") });

    // The editor: change the splitter's distance, save, validate with the CLI.
    await page.click('[data-tab="editor"]');
    await page.waitForSelector(".param-input", { timeout: 20000 });
    const input = page.locator('[data-param="config.pipeline.tracker.splitter.distance"]');
    await input.fill("1.5");
    await input.dispatchEvent("change");
    await page.fill("#editor-path", "edited/mine.yaml");
    await page.click("#editor-save");
    await page.waitForFunction(() => /saved/.test(document.getElementById("editor-result").textContent), null, { timeout: 20000 });
    const saved = join(dir, "edited", "mine.yaml");
    assert.ok(existsSync(saved), "the file was not written under the host's folder");
    assert.match(readFileSync(saved, "utf8"), /distance: 1\.5/);
    const v = spawnSync(plugslam, ["validate", saved], { encoding: "utf8" });
    assert.equal(v.status, 0, v.stdout + v.stderr);
    await page.screenshot({ path: join(artifacts, "page-editor.png") });

    // Outside the folder: refused, nothing written.
    await page.fill("#editor-path", "../escaped.yaml");
    await page.click("#editor-save");
    await page.waitForFunction(() => /not saved/.test(document.getElementById("editor-result").textContent), null, { timeout: 20000 });
    assert.match(await page.textContent("#editor-result"), /refused/);
    assert.ok(!existsSync(join(dir, "..", "escaped.yaml")));
  } finally {
    await browser.close();
    host.kill("SIGINT");
    await new Promise((r) => host.once("exit", r));
    rmSync(dir, { recursive: true, force: true });
  }
});
