// The page's frame rate with a large 2D session, counted in headless Chromium: the bundled page
// is served locally, a synthetic session of N local maps is fed to it, then the frames it
// renders over a few seconds are counted (requestAnimationFrame, one render each).
// Usage: node bench/fps.mjs [--maps 1000] [--points 600] [--seconds 5] [--hide map,grid] [--json]
// --hide turns layers off (the page's layer names) to see what each one costs.
import { browserMissing, launchChromium, serveStatic, webDir } from "../test/support.mjs";
import { syntheticSession } from "./synthetic_session.mjs";

const arg = (name, def) => {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 ? Number(process.argv[i + 1]) : def;
};
const maps = arg("maps", 1000), points = arg("points", 600), seconds = arg("seconds", 5);
const hideAt = process.argv.indexOf("--hide");
const hidden = hideAt > 0 ? process.argv[hideAt + 1].split(",").filter(Boolean) : [];
const missing = browserMissing();
if (missing) {
  console.error(`fps bench skipped: ${missing}`);
  process.exit(2);
}
const server = await serveStatic(webDir);
const browser = await launchChromium();
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 } });
  // No host behind this page: ws://127.0.0.1:9 refuses at once (the page retries quietly).
  await page.goto(`${server.url}/?ws=ws://127.0.0.1:9`);
  await page.waitForFunction(() => window.plugslamView);
  const messages = syntheticSession({ maps, points });
  await page.evaluate((msgs) => msgs.forEach(([t, m]) => window.plugslamView.ingest(t, m)), messages);
  // Let the merged buffers be rebuilt and the page settle before counting.
  await page.waitForFunction((n) => window.plugslamView.counts().mapSourcePoints >= n, maps * points, { timeout: 60000 });
  await page.evaluate((names) => names.forEach((n) => window.plugslamView.view.setVisible(n, false)), hidden);
  await page.waitForTimeout(1000);
  const result = await page.evaluate(async (ms) => {
    const v = window.plugslamView.view;
    const f0 = v.frames, t0 = performance.now();
    await new Promise((r) => setTimeout(r, ms));
    return { frames: v.frames - f0, ms: performance.now() - t0, counts: v.counts() };
  }, seconds * 1000);
  const fps = (result.frames * 1000) / result.ms;
  const out = { maps, points_per_map: points, seconds: result.ms / 1000, frames: result.frames, fps, ...result.counts, hidden, viewport: "1280x800" };
  if (process.argv.includes("--json")) console.log(JSON.stringify(out));
  else console.log(`${maps} local maps x ${points} points: ${fps.toFixed(1)} fps (${result.frames} frames in ${(result.ms / 1000).toFixed(1)} s, ${result.counts.drawCalls} draw calls${hidden.length ? `, hidden: ${hidden.join(",")}` : ""})`);
} finally {
  await browser.close();
  server.close();
}
