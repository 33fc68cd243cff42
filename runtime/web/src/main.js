// The built-in page of `plugslam run --serve` and `plugslam shell --serve`: the live view, run
// controls, a status panel, the camera image and the configuration editor, over the Foxglove
// WebSocket protocol of the host that served it (or of ?ws=ws://HOST:PORT).
import { Connection } from "./connection.js";
import { ConfigEditor } from "./editor.js";
import { SceneView } from "./scene.js";
import { Session } from "./session.js";

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);
const session = new Session();
const view = new SceneView($("view"), session);

// Tests and the frame-rate bench read the page through this object.
window.plugslamView = {
  session,
  view,
  ingest: (topic, msg, schema) => session.ingest(topic, msg, schema),
  fps: () => view.fps(),
  counts: () => view.counts(),
};

function loop(now) {
  view.frame(now);
  requestAnimationFrame(loop);
}
requestAnimationFrame(loop);

// Layers, follow and 2D/3D.
for (const box of document.querySelectorAll("input[data-layer]"))
  box.addEventListener("change", () => view.setVisible(box.dataset.layer, box.checked));
const follow = $("follow");
view.onFollowChange = (on) => (follow.checked = on);
follow.addEventListener("change", () => (view.follow = follow.checked));
$("mode").addEventListener("change", (e) => view.setMode(e.target.value));

// Status panel, refreshed a few times a second.
const kStatus = [
  ["state", "state"],
  ["frame", "frame"],
  ["hz", "Hz"],
  ["local_maps", "local maps"],
  ["loops", "loops"],
  ["tracking_failures", "tracking failures"],
  ["dropped", "dropped (this viewer)"],
];
setInterval(() => {
  const s = session.status;
  const rows = kStatus.map(([k, label]) => {
    let v = s[k];
    if (typeof v === "number" && k === "hz") v = v.toFixed(1);
    return `<tr><td>${label}</td><td data-status="${k}">${v ?? "–"}</td></tr>`;
  });
  const c = view.counts();
  rows.push(`<tr><td>drawn</td><td>${c.localMaps} maps, ${c.mapPoints} points, ${view.fps().toFixed(0)} fps</td></tr>`);
  $("status").innerHTML = rows.join("");
  // Every camera image, one panel each (a stereo pair's left and right, RGB-D's colour and depth).
  const box = $("cameras");
  for (const [topic, { format, data }] of session.images) {
    let panel = [...box.children].find((f) => f.dataset.topic === topic);
    if (!panel) {
      panel = document.createElement("figure");
      panel.dataset.topic = topic;
      const title = document.createElement("figcaption");
      title.className = "muted";
      title.textContent = topic;
      panel.append(title, document.createElement("img"));
      // In topic order, so /camera/left comes before /camera/right whichever arrived first.
      const next = [...box.children].find((f) => f.dataset.topic > topic);
      box.insertBefore(panel, next || null);
    }
    const img = panel.querySelector("img");
    const src = `data:image/${format || "jpeg"};base64,${data}`;
    if (img.dataset.src !== src) {
      img.src = src;
      img.dataset.src = src;
    }
  }
  $("log").textContent = session.log.slice(-8).map((l) => l.message).join("\n");
}, 250);

// The host: same origin unless ?ws= names another.
const url = params.get("ws") || `${location.protocol === "https:" ? "wss" : "ws"}://${location.host}`;
let editor = null;
const connection = new Connection(url, session, {
  onChange: (state) => {
    $("connection").textContent = `${url}: ${state}`;
    $("connection").dataset.state = state;
  },
  onServices: (names) => {
    for (const b of document.querySelectorAll("button[data-service]"))
      b.disabled = !names.includes(b.dataset.service);
    if (names.includes("editor.schema") && !editor) {
      editor = new ConfigEditor($("editor"), connection);
      window.plugslamView.editor = editor;
      editor.load();
    }
  },
});
window.plugslamView.connection = connection;

async function control(service, request) {
  try {
    const r = await connection.call(service, request);
    $("control-result").textContent = r.message || JSON.stringify(r);
  } catch (e) {
    $("control-result").textContent = `${service}: ${e.message}`;
  }
}
$("pause").addEventListener("click", () => control("pause"));
$("resume").addEventListener("click", () => control("resume"));
$("step").addEventListener("click", () => control("step", { count: Number($("step-count").value) || 1 }));

// Tabs: view and editor.
for (const tab of document.querySelectorAll("[data-tab]"))
  tab.addEventListener("click", () => {
    for (const t of document.querySelectorAll("[data-tab]")) t.classList.toggle("active", t === tab);
    for (const p of document.querySelectorAll(".tab-page")) p.hidden = p.id !== `${tab.dataset.tab}-page`;
  });
