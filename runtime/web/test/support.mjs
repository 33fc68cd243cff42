// What the page's tests and bench share: Debian's Chromium through playwright-core (never a
// downloaded browser), a static server for the bundled page, and the build tree's paths.
import { existsSync, readFileSync, statSync } from "node:fs";
import { createServer } from "node:http";
import { extname, join, normalize, resolve, dirname } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
export const sourceDir = resolve(here, "..", "..", "..");
export const buildDir = resolve(process.env.PLUGSLAM_BUILD_DIR || join(sourceDir, "build"));
export const webDir = resolve(process.env.PLUGSLAM_WEB_DIR || join(buildDir, "web"));
export const chromiumPath = process.env.PLUGSLAM_CHROMIUM || "/usr/bin/chromium";

/** Why the browser tests cannot run here, or "" when they can. */
export function browserMissing() {
  if (!existsSync(chromiumPath)) return `no Chromium at ${chromiumPath} (apt-get install chromium)`;
  if (!existsSync(join(webDir, "index.html")))
    return `the page is not built at ${webDir} (scripts/build.sh bundles it)`;
  return "";
}

/** Headless Chromium with the flags known to work on these machines (no network chatter). */
export async function launchChromium() {
  const { chromium } = await import("playwright-core");
  return chromium.launch({
    executablePath: chromiumPath,
    headless: true,
    args: [
      "--no-sandbox",
      "--disable-gpu",
      "--disable-quic",
      "--no-first-run",
      "--disable-background-networking",
      "--disable-component-update",
      "--disable-sync",
      "--use-gl=angle",
      "--use-angle=swiftshader",
      "--enable-unsafe-swiftshader",
    ],
  });
}

const kTypes = { ".html": "text/html", ".js": "text/javascript", ".css": "text/css", ".map": "application/json" };

/** Serves `dir` on a free loopback port; resolves with {url, close}. */
export function serveStatic(dir) {
  const server = createServer((req, res) => {
    const path = normalize(decodeURIComponent(new URL(req.url, "http://x").pathname));
    const file = join(dir, path === "/" ? "index.html" : path);
    if (!file.startsWith(dir) || !existsSync(file) || !statSync(file).isFile()) {
      res.writeHead(404).end("not found");
      return;
    }
    res.writeHead(200, { "content-type": kTypes[extname(file)] || "application/octet-stream" });
    res.end(readFileSync(file));
  });
  return new Promise((ok) =>
    server.listen(0, "127.0.0.1", () =>
      ok({ url: `http://127.0.0.1:${server.address().port}`, close: () => server.close() }),
    ),
  );
}
