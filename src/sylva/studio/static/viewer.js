// The 3D canvas: the plant mesh (GLB from the server), the focus point and LSysVis's camera.
//
// Camera (seed 001 §5.4–5.5): an orbit around the focus point, which is always at the canvas
// centre.  Modes: "perspective", "orthographic" (3D) and "2d" (orthographic, looking down -Z
// at the XY plane, rotation locked).  The distance to the focus point is 1.001^zoom; the wheel
// changes zoom.  Left-drag orbits (pans in 2D), right-drag pans in the plane parallel to the
// screen, middle-drag moves the focus point along the view axis.  Yaw and pitch follow
// sylva.render.Camera, so a PNG rendered by the server matches the view.
import * as THREE from "./vendor/three.js";

const FOV = 45;
const ZOOM_BASE = 1.001;

// Bark and leaf: the GLSL of their texture graphs (sylva.texture.graph.surface, served as
// /api/surfaces.glsl), the functions the renderer calls and the exports bake, run on each
// surface's (u, v).  The GLB names a material's procedural texture in extras.sylva_texture.
const SURFACE_CHUNKS = {
  bark: "{ vec4 sylvaT = sylva_bark_graph(vec3(vUv, 0.0)); diffuseColor.rgb *= sylvaT.r; }",
  leaf: "{ vec4 sylvaT = sylva_leaf_graph(vec3(vUv, 0.0));\n" +
    "  vec3 sylvaB = min(diffuseColor.rgb * 1.7 + vec3(0.06, 0.07, 0.03), vec3(1.0));\n" +
    "  diffuseColor.rgb = mix(diffuseColor.rgb * sylvaT.r, sylvaB, sylvaT.g); }",
};
let surfaceGlsl = null;

// The graphs' GLSL, fetched once ("" where the page has no server that serves it).
export function surfaceSource() {
  if (surfaceGlsl === null) {
    surfaceGlsl = fetch("/api/surfaces.glsl")
      .then((r) => (r.ok ? r.text() : ""))
      .catch(() => "");
  }
  return surfaceGlsl;
}

// A glTF material drawing its procedural texture with the graph's GLSL (the base colour,
// linear as in the renderer, times or mixed with the graph's channels, as textures.glsl does).
export function surfaceMaterial(material, kind, glsl) {
  material.defines = { ...(material.defines || {}), USE_UV: "" };
  material.onBeforeCompile = (shader) => {
    shader.fragmentShader = shader.fragmentShader
      .replace("#include <common>", "#include <common>\n" + glsl)
      .replace("#include <map_fragment>", "#include <map_fragment>\n" + SURFACE_CHUNKS[kind]);
  };
  material.customProgramCacheKey = () => "sylva-surface-" + kind;
  material.userData.sylvaSurface = kind;
  material.needsUpdate = true;
}

export class Viewer {
  constructor(canvas, { onPick, onCamera } = {}) {
    this.canvas = canvas;
    this.onPick = onPick || (() => {});
    this.onCamera = onCamera || (() => {});
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(window.devicePixelRatio || 1, 2));
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(0.9, 0.9, 0.9);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x8a8a80, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(3, 5, 4);
    this.scene.add(sun);
    this.plant = new THREE.Group();
    this.scene.add(this.plant);
    this.focus = makeAxisCross();
    this.scene.add(this.focus);
    this.highlight = new THREE.Group();
    this.scene.add(this.highlight);
    this.perspective = new THREE.PerspectiveCamera(FOV, 1, 0.01, 1000);
    this.ortho = new THREE.OrthographicCamera(-1, 1, 1, -1, 0.01, 1000);
    this.mode = "2d";
    this.target = new THREE.Vector3();
    this.yaw = 0;
    this.pitch = 0;
    this.zoom = Math.log(10) / Math.log(ZOOM_BASE);
    this.bounds = null;
    this.triangles = 0;
    this.lines = 0;  // branches drawn as the preview's lines
    this.kind = null;  // what is shown: "glb", "segments" or "preview"
    this.drawMs = 0;
    this.raycaster = new THREE.Raycaster();
    this._dirty = true;
    this._bindInput();
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
    const loop = () => {
      if (this._dirty) { this._render(); this.renderedAt = performance.now(); }
      requestAnimationFrame(loop);
    };
    requestAnimationFrame(loop);
  }

  get radius() { return Math.pow(ZOOM_BASE, this.zoom); }
  set radius(r) { this.zoom = Math.log(Math.max(r, 1e-6)) / Math.log(ZOOM_BASE); }

  resize() {
    const w = Math.max(1, this.canvas.clientWidth), h = Math.max(1, this.canvas.clientHeight);
    this.renderer.setSize(w, h, false);
    this.invalidate();
  }

  invalidate() { this._dirty = true; }

  setMode(mode) {
    this.mode = mode;
    if (mode === "2d") { this.yaw = 0; this.pitch = 0; }
    this.invalidate();
    this._emitCamera();
  }

  setBackground(rgb) {
    const c = rgb || [0.9, 0.9, 0.9];
    const color = new THREE.Color().setRGB(c[0], c[1], c[2], THREE.SRGBColorSpace);
    // the same colour again draws nothing new (a large plant's frame costs seconds in
    // software WebGL)
    if (this.scene.background && this.scene.background.equals(color)) return;
    this.scene.background = color;
    this.invalidate();
  }

  setFocusVisible(on) { this.focus.visible = on; this.invalidate(); }

  // the backward unit vector (target -> eye), as sylva.render.Camera.basis()
  _back() {
    const y = THREE.MathUtils.degToRad(this.yaw), p = THREE.MathUtils.degToRad(this.pitch);
    return new THREE.Vector3(Math.cos(p) * Math.sin(y), Math.sin(p), Math.cos(p) * Math.cos(y));
  }

  get camera() { return this.mode === "perspective" ? this.perspective : this.ortho; }

  get eye() { return this.target.clone().addScaledVector(this._back(), this.radius); }

  orthoHeight() { return 2 * this.radius * Math.tan(THREE.MathUtils.degToRad(FOV / 2)); }

  _place() {
    const w = Math.max(1, this.canvas.clientWidth), h = Math.max(1, this.canvas.clientHeight);
    const aspect = w / h;
    const r = this.radius;
    const size = this.bounds ? this.bounds.getSize(new THREE.Vector3()).length() : 10;
    const near = Math.max(r * 1e-3, 1e-4), far = r * 4 + size * 4 + 10;
    const cam = this.camera;
    if (this.mode === "perspective") {
      cam.aspect = aspect;
      cam.fov = FOV;
    } else {
      const hh = this.orthoHeight() / 2;
      cam.left = -hh * aspect; cam.right = hh * aspect; cam.top = hh; cam.bottom = -hh;
    }
    cam.near = near;
    cam.far = far;
    cam.position.copy(this.eye);
    cam.up.set(0, 1, 0);
    if (Math.abs(this.pitch) > 89.5) {
      // keep the frame continuous at the poles
      const y = THREE.MathUtils.degToRad(this.yaw);
      cam.up.set(-Math.sin(y) * Math.sign(this.pitch), 0, -Math.cos(y) * Math.sign(this.pitch));
    }
    cam.lookAt(this.target);
    cam.updateProjectionMatrix();
    this.focus.position.copy(this.target);
  }

  _render() {
    this._dirty = false;
    this._place();
    const t0 = performance.now();
    if (this.kind === "preview") {
      this._previewRenderer().render(this.scene, this.camera);
      this._previewCanvas.style.visibility = "visible";
    } else {
      this.renderer.render(this.scene, this.camera);
      if (this._previewCanvas) this._previewCanvas.style.visibility = "hidden";
    }
    this.drawMs = performance.now() - t0;
  }

  // The renderer of the frame shown: the preview's or the main one.
  get activeRenderer() { return this.kind === "preview" ? this._previewRenderer() : this.renderer; }

  // The preview draws on a canvas of its own laid over the main one, without
  // multisampling: in software WebGL a multisampled frame of lines costs three times as
  // much, and a one-pixel line gains nothing from it.  The main canvas keeps its antialiased
  // frame for the full-quality plant.
  _previewRenderer() {
    const m = this.canvas;
    if (!this._preview) {
      const c = document.createElement("canvas");
      c.className = "sylva-preview";
      Object.assign(c.style, { position: "absolute", margin: "0", border: "0", padding: "0",
        pointerEvents: "none", visibility: "hidden" });
      m.parentNode.insertBefore(c, m.nextSibling);
      this._previewCanvas = c;
      this._preview = new THREE.WebGLRenderer({ canvas: c, antialias: false, preserveDrawingBuffer: true });
      this._preview.setPixelRatio(this.renderer.getPixelRatio());
    }
    const c = this._previewCanvas;
    const w = Math.max(1, m.clientWidth), h = Math.max(1, m.clientHeight);
    c.style.left = `${m.offsetLeft + m.clientLeft}px`;
    c.style.top = `${m.offsetTop + m.clientTop}px`;
    c.style.width = `${w}px`;
    c.style.height = `${h}px`;
    const size = this._preview.getSize(new THREE.Vector2());
    if (size.x !== w || size.y !== h) this._preview.setSize(w, h, false);
    return this._preview;
  }

  // -------------------------------------------------------------------- the plant
  async showGlb(buffer, { fit = false } = {}) {
    const { GLTFLoader } = THREE;
    const gltf = await new Promise((resolve, reject) =>
      new GLTFLoader().parse(buffer, "", resolve, reject));
    const textured = [];
    gltf.scene.traverse((o) => {
      if (!o.isMesh || !o.geometry.attributes.uv) return;
      for (const m of Array.isArray(o.material) ? o.material : [o.material]) {
        const kind = m.userData && m.userData.sylva_texture;
        if (SURFACE_CHUNKS[kind] && !m.map) textured.push([m, kind]);
      }
    });
    const glsl = textured.length ? await surfaceSource() : "";
    if (glsl) for (const [m, kind] of textured) surfaceMaterial(m, kind, glsl);
    this._disposePlant();
    let triangles = 0;
    gltf.scene.traverse((o) => {
      if (o.isMesh) {
        const g = o.geometry;
        triangles += (g.index ? g.index.count : g.attributes.position.count) / 3;
        const mats = Array.isArray(o.material) ? o.material : [o.material];
        for (const m of mats) m.side = THREE.DoubleSide;
        if (o.isSkinnedMesh) o.frustumCulled = false;  // wind moves it out of its box
      }
    });
    this.plant.add(gltf.scene);
    this.triangles = triangles;
    this.kind = "glb";
    this.plant.updateMatrixWorld(true);
    const box = new THREE.Box3().setFromObject(this.plant);
    this.bounds = box.isEmpty() ? null : box;
    if (fit) this.resetCamera();
    this.clearHighlight();
    this.invalidate();
    return gltf;  // its animations are the caller's (the notebook widget plays the wind)
  }

  // Branches as instanced cylinders: float32 rows of 11 (start xyz, end xyz, r0, r1, linear
  // rgb), one shared 8-sided cylinder scaled and turned per branch (LSysVis's TurtleVAO,
  // seed 001 §6.7); what the server sends for a plant of many branches.
  showSegments(buffer, { fit = false } = {}) {
    const f = new Float32Array(buffer);
    this._disposePlant();
    const n = Math.floor(f.length / 11);
    // one cylinder and one material for every plant: a new material each time would
    // compile its shader program again
    if (!this._cylinder) {
      this._cylinder = new THREE.CylinderGeometry(1, 1, 1, 8, 1, true);
      this._cylinder.translate(0, 0.5, 0);  // from the origin along +Y
      this._cylinderMaterial = new THREE.MeshStandardMaterial({ roughness: 0.8, metalness: 0, side: THREE.DoubleSide });
    }
    const geo = this._cylinder, mat = this._cylinderMaterial;
    const mesh = new THREE.InstancedMesh(geo, mat, n);
    mesh.userData.shared = true;  // its geometry and material outlive it
    const m = new THREE.Matrix4(), q = new THREE.Quaternion(), scale = new THREE.Vector3();
    const p = new THREE.Vector3(), d = new THREE.Vector3(), up = new THREE.Vector3(0, 1, 0);
    const c = new THREE.Color(), box = new THREE.Box3();
    for (let i = 0, k = 0; i < n; i++, k += 11) {
      p.set(f[k], f[k + 1], f[k + 2]);
      d.set(f[k + 3] - f[k], f[k + 4] - f[k + 1], f[k + 5] - f[k + 2]);
      const len = d.length();
      const r = 0.5 * (f[k + 6] + f[k + 7]);
      if (len > 0) q.setFromUnitVectors(up, d.multiplyScalar(1 / len)); else q.identity();
      m.compose(p, q, scale.set(r, len, r));
      mesh.setMatrixAt(i, m);
      mesh.setColorAt(i, c.setRGB(f[k + 8], f[k + 9], f[k + 10], THREE.LinearSRGBColorSpace));
      box.expandByPoint(p);
      box.expandByPoint(p.set(f[k + 3], f[k + 4], f[k + 5]));
    }
    mesh.instanceMatrix.needsUpdate = true;
    if (mesh.instanceColor) mesh.instanceColor.needsUpdate = true;
    mesh.computeBoundingSphere();
    this.plant.add(mesh);
    this.triangles = n * geo.index.count / 3;
    this.kind = "segments";
    this.bounds = box.isEmpty() ? null : box;
    if (fit) this.resetCamera();
    this.clearHighlight();
    this.invalidate();
  }

  // The preview while a slider moves: the branches as one-pixel lines, no triangles
  // (sylva._lines: n * 6 float32 end points, then n * 8 uint8 RGBA colours, linear).  The
  // bytes are the vertex buffers as they come; the full frame (showSegments or showGlb)
  // replaces it.
  showLines(buffer, { fit = false } = {}) {
    const n = Math.floor(buffer.byteLength / 32);
    this._disposePlant();
    const geo = new THREE.BufferGeometry();
    geo.setAttribute("position", new THREE.BufferAttribute(new Float32Array(buffer, 0, n * 6), 3));
    geo.setAttribute("color", new THREE.BufferAttribute(new Uint8Array(buffer, n * 24, n * 8), 4, true));
    geo.computeBoundingBox();
    geo.computeBoundingSphere();
    if (!this._lineMaterial) {
      this._lineMaterial = new THREE.LineBasicMaterial({ vertexColors: true });
    }
    const lines = new THREE.LineSegments(geo, this._lineMaterial);
    lines.userData.sharedMaterial = true;
    this.plant.add(lines);
    this.triangles = 0;
    this.lines = n;
    this.kind = "preview";
    this.bounds = n ? geo.boundingBox.clone() : null;
    if (fit) this.resetCamera();
    this.clearHighlight();
    this.invalidate();
  }

  _disposePlant() {
    this.plant.traverse((o) => {
      if (o.isLineSegments && o.userData.sharedMaterial) {
        o.geometry.dispose();
      } else if (o.isInstancedMesh && o.userData.shared) {
        o.dispose();  // its instance buffers; the cylinder and material are kept
      } else if (o.isMesh) {
        o.geometry.dispose();
        const mats = Array.isArray(o.material) ? o.material : [o.material];
        for (const m of mats) m.dispose();
      }
    });
    this.plant.clear();
  }

  clear() {
    this._disposePlant();
    this.bounds = null; this.triangles = 0; this.lines = 0; this.kind = null;
    this.invalidate();
  }

  // Reset camera: frame the whole plant, looking at its centre.
  resetCamera() {
    const box = this.bounds;
    if (this.mode === "2d") { this.yaw = 0; this.pitch = 0; } else { this.yaw = 30; this.pitch = 20; }
    if (box) {
      box.getCenter(this.target);
      const size = box.getSize(new THREE.Vector3());
      const w = Math.max(1, this.canvas.clientWidth), h = Math.max(1, this.canvas.clientHeight);
      const aspect = w / h;
      const extent = this.mode === "2d" ? Math.max(size.y, size.x / aspect)
        : Math.max(size.length(), 1e-3);
      const half = Math.tan(THREE.MathUtils.degToRad(FOV / 2));
      this.radius = Math.max(extent, 1e-3) * 0.55 / half + (this.mode === "2d" ? 0 : 0);
    } else {
      this.target.set(0, 0, 0);
      this.radius = 10;
    }
    this.invalidate();
    this._emitCamera();
  }

  highlightSegment(seg) {
    this.clearHighlight();
    if (!seg) return;
    const a = new THREE.Vector3(...seg.start), b = new THREE.Vector3(...seg.end);
    const len = a.distanceTo(b);
    const r = Math.max(seg.radius * 1.35, (this.radius || 1) * 0.002);
    const geo = new THREE.CylinderGeometry(r, r, Math.max(len, 1e-6), 12, 1);
    const mat = new THREE.MeshBasicMaterial({ color: 0xff7a00, depthTest: false, transparent: true, opacity: 0.85 });
    const m = new THREE.Mesh(geo, mat);
    m.position.copy(a).add(b).multiplyScalar(0.5);
    m.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), b.clone().sub(a).normalize());
    m.renderOrder = 10;
    this.highlight.add(m);
    this.invalidate();
  }

  highlightPoint(p) {
    this.clearHighlight();
    const r = (this.radius || 1) * 0.01;
    const m = new THREE.Mesh(new THREE.SphereGeometry(r, 12, 8),
      new THREE.MeshBasicMaterial({ color: 0xff7a00, depthTest: false }));
    m.position.set(...p);
    m.renderOrder = 10;
    this.highlight.add(m);
    this.invalidate();
  }

  clearHighlight() {
    this.highlight.traverse((o) => { if (o.isMesh) { o.geometry.dispose(); o.material.dispose(); } });
    this.highlight.clear();
    this.invalidate();
  }

  // -------------------------------------------------------------------- state for others
  cameraState() {
    const e = this.eye;
    return {
      mode: this.mode,
      target: this.target.toArray(),
      yaw: this.yaw,
      pitch: this.pitch,
      distance: this.radius,
      zoom: this.zoom,
      fov: FOV,
      height: this.orthoHeight(),
      position: e.toArray(),
    };
  }

  _emitCamera() { this.onCamera(this.cameraState()); }

  // -------------------------------------------------------------------- input
  _worldPerPixel() {
    const h = Math.max(1, this.canvas.clientHeight);
    return this.orthoHeight() / h;
  }

  _pan(dx, dy) {
    const cam = this.camera;
    this._place();
    const right = new THREE.Vector3().setFromMatrixColumn(cam.matrixWorld, 0);
    const up = new THREE.Vector3().setFromMatrixColumn(cam.matrixWorld, 1);
    const k = this._worldPerPixel();
    this.target.addScaledVector(right, -dx * k).addScaledVector(up, dy * k);
  }

  _bindInput() {
    const c = this.canvas;
    let drag = null;
    c.addEventListener("contextmenu", (e) => e.preventDefault());
    c.addEventListener("pointerdown", (e) => {
      c.focus();
      c.setPointerCapture(e.pointerId);
      drag = { x: e.clientX, y: e.clientY, x0: e.clientX, y0: e.clientY, button: e.button };
    });
    c.addEventListener("pointermove", (e) => {
      if (!drag) return;
      const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
      drag.x = e.clientX; drag.y = e.clientY;
      const orbit = drag.button === 0 && this.mode !== "2d";
      if (orbit) {
        this.yaw -= dx * 0.4;
        this.pitch = Math.max(-90, Math.min(90, this.pitch + dy * 0.4));
      } else if (drag.button === 1 && this.mode !== "2d") {
        const fwd = this._back().negate();
        this.target.addScaledVector(fwd, -dy * this._worldPerPixel());
      } else {
        this._pan(dx, dy);
      }
      this.invalidate();
      this._emitCamera();
    });
    c.addEventListener("pointerup", (e) => {
      if (!drag) return;
      const moved = Math.hypot(e.clientX - drag.x0, e.clientY - drag.y0);
      const click = drag.button === 0 && moved < 4;
      drag = null;
      c.releasePointerCapture(e.pointerId);
      if (click) this.pickAt(e.clientX, e.clientY);
    });
    c.addEventListener("wheel", (e) => {
      e.preventDefault();
      const step = e.deltaMode === 1 ? e.deltaY * 33 : e.deltaY;
      this.zoom += step;
      this.invalidate();
      this._emitCamera();
    }, { passive: false });
  }

  // The point on the plant under the pixel (clientX, clientY), or null.
  hitAt(clientX, clientY) {
    const rect = this.canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((clientX - rect.left) / rect.width) * 2 - 1,
      -((clientY - rect.top) / rect.height) * 2 + 1);
    this._place();
    this.raycaster.setFromCamera(ndc, this.camera);
    const hits = this.raycaster.intersectObject(this.plant, true);
    return hits.length ? hits[0].point : null;
  }

  pickAt(clientX, clientY) {
    const p = this.hitAt(clientX, clientY);
    if (p) this.onPick(p.toArray());
  }

  // The canvas pixel of a model-space point (for tests and tools).
  project(point) {
    this._place();
    const v = new THREE.Vector3(...point).project(this.camera);
    const rect = this.canvas.getBoundingClientRect();
    return [rect.left + (v.x + 1) / 2 * rect.width, rect.top + (1 - v.y) / 2 * rect.height];
  }
}

// The focus point: +X red, +Y blue, +Z green, each of length 1 (seed 001 §4.5).
function makeAxisCross() {
  const g = new THREE.Group();
  const axes = [[[1, 0, 0], 0xff0000], [[0, 1, 0], 0x0000ff], [[0, 0, 1], 0x00aa00]];
  for (const [dir, color] of axes) {
    const geo = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3(...dir)]);
    const line = new THREE.Line(geo, new THREE.LineBasicMaterial({ color, depthTest: false }));
    line.renderOrder = 5;
    g.add(line);
  }
  return g;
}
