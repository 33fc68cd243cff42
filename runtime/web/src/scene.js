// The 2D/3D view of a Session with three.js. Everything of the local maps (their points, their
// occupied cells, the trajectory, the graph) is merged into a handful of world-frame buffers, so a
// session of thousands of local maps still costs a few draw calls per frame; the buffers are
// rebuilt only when the session changed (a new map, a corrected map origin), at most a few times
// a second.
import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import { apply, yawOf } from "./session.js";

const kRebuildMs = 250;

function pointsObject(color, size) {
  const g = new THREE.BufferGeometry();
  g.setAttribute("position", new THREE.Float32BufferAttribute([], 3));
  const m = new THREE.PointsMaterial({ color, size, sizeAttenuation: false });
  return new THREE.Points(g, m);
}

function linesObject(color, opacity = 1) {
  const g = new THREE.BufferGeometry();
  g.setAttribute("position", new THREE.Float32BufferAttribute([], 3));
  const m = new THREE.LineBasicMaterial({ color, transparent: opacity < 1, opacity });
  return new THREE.LineSegments(g, m);
}

function setPositions(obj, array) {
  obj.geometry.setAttribute("position", new THREE.BufferAttribute(array, 3));
  obj.geometry.computeBoundingSphere();
}

// One point per cell of `cell` metres (the first seen), exact keys for |coordinate| < 2^20 cells.
function thin(points, cell) {
  if (!(cell > 0)) return points;
  const seen = new Set();
  const out = new Float32Array(points.length);
  let n = 0;
  const half = 2 ** 20;
  for (let i = 0; i < points.length; i += 3) {
    const kx = Math.floor(points[i] / cell) + half, ky = Math.floor(points[i + 1] / cell) + half;
    const kz = Math.min(1023, Math.max(0, Math.floor(points[i + 2] / cell) + 512));
    const key = (kz * 2 ** 21 + kx) * 2 ** 21 + ky;
    if (seen.has(key)) continue;
    seen.add(key);
    out[n++] = points[i];
    out[n++] = points[i + 1];
    out[n++] = points[i + 2];
  }
  return out.subarray(0, n);
}

/** The three.js view of a session in a canvas. */
export class SceneView {
  constructor(canvas, session) {
    this.session = session;
    this.canvas = canvas;
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.renderer.setClearColor(0xf4f4f4);
    this.scene = new THREE.Scene();
    this.layers = {
      map: pointsObject(0x202020, 2),
      grid: pointsObject(0x505050, 2),
      trajectory: linesObject(0x1f77b4),
      odometry: linesObject(0x7f7f7f, 0.6),
      loops: linesObject(0xd62728, 0.35),
      nodes: pointsObject(0x173c6e, 4),
      scan: pointsObject(0xff7f0e, 3),
      track: linesObject(0x2ca02c),
    };
    for (const o of Object.values(this.layers)) this.scene.add(o);
    this.robot = new THREE.Mesh(
      new THREE.ConeGeometry(0.18, 0.5, 3).rotateZ(-Math.PI / 2),
      new THREE.MeshBasicMaterial({ color: 0x2ca02c }),
    );
    this.scene.add(this.robot);
    this.grid = new THREE.GridHelper(200, 200, 0xdddddd, 0xe8e8e8);
    this.grid.rotateX(Math.PI / 2);
    this.scene.add(this.grid);
    this.follow = true;
    this.mode = "2d";
    this.built = -1;
    this.scanBuilt = -1;
    this.lastBuild = 0;
    this.frames = 0;
    this.frameTimes = [];
    this.setMode("2d");
    this.watchPan();
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
  }

  /** "2d": top-down orthographic, pan and zoom; "3d": perspective orbit. */
  setMode(mode) {
    this.mode = mode;
    const target = this.controls ? this.controls.target.clone() : new THREE.Vector3();
    if (this.controls) this.controls.dispose();
    if (mode === "2d") {
      this.camera = new THREE.OrthographicCamera(-10, 10, 10, -10, -1000, 1000);
      this.camera.position.set(target.x, target.y, 100);
      this.camera.up.set(0, 1, 0);
      this.zoomSpan = 30;
    } else {
      this.camera = new THREE.PerspectiveCamera(60, 1, 0.05, 5000);
      this.camera.up.set(0, 0, 1);
      this.camera.position.set(target.x - 12, target.y - 12, 12);
    }
    this.controls = new OrbitControls(this.camera, this.canvas);
    this.controls.enableRotate = mode === "3d";
    this.controls.screenSpacePanning = true;
    if (mode === "2d") {
      // A top view has nothing to rotate: the left button (and one finger) pan.
      this.controls.mouseButtons = { LEFT: THREE.MOUSE.PAN, MIDDLE: THREE.MOUSE.DOLLY, RIGHT: THREE.MOUSE.PAN };
      this.controls.touches = { ONE: THREE.TOUCH.PAN, TWO: THREE.TOUCH.DOLLY_PAN };
    }
    this.controls.target.copy(target);
    this.controls.update();
    this.resize();
  }

  // Panning is the user taking the camera: follow-the-robot stops (the checkbox turns it on
  // again). Zooming (wheel, pinch) and orbiting keep following: they do not move the target.
  // A pan is a drag that starts a pan in OrbitControls' own mapping of buttons and modifiers.
  watchPan() {
    const pointers = new Set();
    let candidate = false;
    const startsPan = (e) => {
      const c = this.controls;
      if (!c.enablePan) return false;
      if (e.pointerType === "touch") return c.touches.ONE === THREE.TOUCH.PAN;
      const action = [c.mouseButtons.LEFT, c.mouseButtons.MIDDLE, c.mouseButtons.RIGHT][e.button];
      const modified = e.ctrlKey || e.metaKey || e.shiftKey;
      return (action === THREE.MOUSE.PAN && !modified) || (action === THREE.MOUSE.ROTATE && modified);
    };
    this.canvas.addEventListener("pointerdown", (e) => {
      pointers.add(e.pointerId);
      candidate = pointers.size === 1 && startsPan(e);
    });
    this.canvas.addEventListener("pointermove", () => {
      // A second finger first makes it a pinch; a click that does not move pans nothing.
      if (!candidate || pointers.size !== 1) return;
      candidate = false;
      if (this.follow) {
        this.follow = false;
        if (this.onFollowChange) this.onFollowChange(false);
      }
    });
    const up = (e) => {
      pointers.delete(e.pointerId);
      if (pointers.size !== 1) candidate = false;
    };
    this.canvas.addEventListener("pointerup", up);
    this.canvas.addEventListener("pointercancel", up);
  }

  resize() {
    const w = this.canvas.clientWidth || 640, h = this.canvas.clientHeight || 480;
    this.renderer.setSize(w, h, false);
    if (this.camera.isOrthographicCamera) {
      const span = this.zoomSpan || 30, aspect = w / h;
      this.camera.left = (-span * aspect) / 2;
      this.camera.right = (span * aspect) / 2;
      this.camera.top = span / 2;
      this.camera.bottom = -span / 2;
    } else {
      this.camera.aspect = w / h;
    }
    this.camera.updateProjectionMatrix();
  }

  /** Shows or hides a layer by name. */
  setVisible(layer, on) {
    if (this.layers[layer]) this.layers[layer].visible = on;
  }

  // Each local map's points in world coordinates are cached and recomputed only when its origin
  // (a loop closure moves it) or its content changed; the layers are then one copy of them all.
  rebuild() {
    const s = this.session;
    const parts = { map: [], grid: [], trajectory: [] };
    for (const [frame, m] of s.maps) {
      const W = s.worldOf(frame);
      const key = `${m.rev}|${W.t.join(",")}|${W.q.join(",")}`;
      if (!m.world || m.world.key !== key) {
        const move = (src) => {
          const out = new Float32Array(src.length);
          for (let i = 0; i < src.length; i += 3) out.set(apply(W, [src[i], src[i + 1], src[i + 2]]), i);
          return out;
        };
        const traj = new Float32Array(Math.max(0, m.trajectory.length - 1) * 6);
        for (let i = 0; i + 1 < m.trajectory.length; ++i)
          traj.set([...apply(W, m.trajectory[i]), ...apply(W, m.trajectory[i + 1])], 6 * i);
        m.world = {
          key,
          map: [...m.clouds.values()].map(move),
          grid: m.grid ? [move(m.grid)] : [],
          trajectory: [traj],
        };
      }
      for (const layer of ["map", "grid", "trajectory"]) parts[layer].push(...m.world[layer]);
    }
    // More than one point per pixel is invisible work: map points and cells are thinned to one
    // per screen pixel at the current zoom (rebuilt when the zoom changes by half or double).
    const cell = this.pixelSize();
    for (const layer of ["map", "grid", "trajectory"]) {
      const total = parts[layer].reduce((n, a) => n + a.length, 0);
      let out = new Float32Array(total);
      let at = 0;
      for (const a of parts[layer]) {
        out.set(a, at);
        at += a.length;
      }
      if (layer === "map") this.sourcePoints = out.length / 3;
      if (layer !== "trajectory") out = thin(out, cell);
      setPositions(this.layers[layer], out);
    }
    this.builtCell = cell;
    setPositions(this.layers.odometry, new Float32Array(s.graph.odometry.flat()));
    setPositions(this.layers.loops, new Float32Array(s.graph.loops.flat()));
    setPositions(this.layers.nodes, new Float32Array(s.graph.nodes.flat()));
    this.built = s.version;
  }

  /** Metres per screen pixel at the camera's target. */
  pixelSize() {
    const h = this.canvas.clientHeight || 480;
    if (this.camera.isOrthographicCamera) return (this.camera.top - this.camera.bottom) / this.camera.zoom / h;
    const d = this.camera.position.distanceTo(this.controls.target);
    return (2 * d * Math.tan((this.camera.fov * Math.PI) / 360)) / h;
  }

  update(now) {
    const s = this.session;
    const zoomed = this.builtCell && Math.abs(Math.log2(this.pixelSize() / this.builtCell)) > 1;
    if ((this.built !== s.version || zoomed) && now - this.lastBuild > kRebuildMs) {
      this.rebuild();
      this.lastBuild = now;
    }
    if (this.scanBuilt !== s.scanVersion && s.scan) {
      const W = s.scan.frame === "base_link" && s.robot ? s.robot : s.worldOf(s.scan.frame);
      const p = s.scan.points, out = new Float32Array(p.length);
      for (let i = 0; i < p.length; i += 3) out.set(apply(W, [p[i], p[i + 1], p[i + 2]]), i);
      setPositions(this.layers.scan, out);
      this.scanBuilt = s.scanVersion;
    }
    if (s.robotTrack.length > 1 && this.trackBuilt !== s.robotTrack.length) {
      const t = s.robotTrack, out = new Float32Array((t.length - 1) * 6);
      for (let i = 0; i + 1 < t.length; ++i) out.set([...t[i], ...t[i + 1]], 6 * i);
      setPositions(this.layers.track, out);
      this.trackBuilt = t.length;
    }
    if (s.robot) {
      this.robot.visible = true;
      this.robot.position.set(...s.robot.t);
      this.robot.rotation.set(0, 0, yawOf(s.robot));
      if (this.follow) {
        const target = new THREE.Vector3(...s.robot.t);
        const delta = target.clone().sub(this.controls.target);
        this.controls.target.copy(target);
        this.camera.position.add(delta);
      }
    } else {
      this.robot.visible = false;
    }
    if (this.camera.isOrthographicCamera) {
      // OrbitControls zooms an orthographic camera through .zoom; the span stays put.
      this.camera.updateProjectionMatrix();
    }
    this.controls.update();
  }

  /** Draws one frame; returns nothing. Counted for the frame-rate figures. */
  frame(now) {
    this.update(now);
    this.renderer.render(this.scene, this.camera);
    ++this.frames;
    this.frameTimes.push(now);
    while (this.frameTimes.length && now - this.frameTimes[0] > 2000) this.frameTimes.shift();
  }

  /** Frames per second over the last two seconds. */
  fps() {
    const t = this.frameTimes;
    return t.length > 1 ? ((t.length - 1) * 1000) / (t[t.length - 1] - t[0]) : 0;
  }

  /** Counts of what is drawn (for tests and the status panel). */
  counts() {
    const n = (o) => (o.geometry.getAttribute("position") ? o.geometry.getAttribute("position").count : 0);
    return {
      localMaps: this.session.localMaps(),
      mapPoints: n(this.layers.map),
      mapSourcePoints: this.sourcePoints || 0,
      gridCells: n(this.layers.grid),
      trajectoryVertices: n(this.layers.trajectory),
      loopVertices: n(this.layers.loops),
      scanPoints: n(this.layers.scan),
      drawCalls: this.renderer.info.render.calls,
    };
  }
}
