// The notebook view of sylva (an anywidget front end): the studio's own Viewer and three.js.
//
// The Python side (sylva/widgets/_view.py) sends the mesh as a binary glTF in the `glb`
// trait (a binary buffer of the comm, no JSON), a large plant's branches as instanced rows
// in `segments`, and while a slider is dragged their preview as lines in `lines` (the full
// frame follows when it rests); this module draws them with the studio's
// Viewer (static/viewer.js: the same lights, camera, orbit, pan and zoom) and three.js
// bundle (static/vendor/three.js), both inlined below by Python when the widget is made,
// so nothing is fetched from the network.  A step slider asks for another derivation
// step; a glTF with an animation (a tree's wind) plays in a loop.
const THREE_SOURCE = __THREE_SOURCE__;
const VIEWER_SOURCE = __VIEWER_SOURCE__;

let loaded = null;
function load() {
  // three.js and the Viewer as modules from blob URLs: the Viewer's import of
  // "./vendor/three.js" is pointed at three.js's blob
  if (!loaded) {
    const url = (text) => URL.createObjectURL(new Blob([text], { type: "text/javascript" }));
    const threeUrl = url(THREE_SOURCE);
    const viewerUrl = url(VIEWER_SOURCE.replace('"./vendor/three.js"', JSON.stringify(threeUrl)));
    loaded = Promise.all([import(threeUrl), import(viewerUrl)]);
  }
  return loaded;
}

const CSS = `
.sylva-view { font: 12px system-ui, sans-serif; color: #222; }
.sylva-view canvas { display: block; width: 100%; border-radius: 4px; outline: none;
  touch-action: none; }
.sylva-view .bar { display: flex; gap: 8px; align-items: center; padding: 4px 0;
  flex-wrap: wrap; }
.sylva-view .bar input[type=range] { flex: 1; min-width: 120px; }
.sylva-view .status { color: #555; }
.sylva-view .status.error { color: #b00020; font-weight: 600; }
.sylva-view button, .sylva-view select { font: inherit; }
`;

function el(tag, props = {}, ...children) {
  const e = document.createElement(tag);
  Object.assign(e, props);
  for (const c of children) e.append(c);
  return e;
}

function arrayBuffer(value) {
  if (!value) return null;
  if (value instanceof ArrayBuffer) return value;
  if (ArrayBuffer.isView(value)) {
    return value.buffer.slice(value.byteOffset, value.byteOffset + value.byteLength);
  }
  return null;
}

async function render({ model, el: host }) {
  const [THREE, { Viewer }] = await load();
  const root = el("div", { className: "sylva-view" });
  root.append(el("style", { textContent: CSS }));
  const canvas = el("canvas", { tabIndex: 0 });
  canvas.style.height = `${model.get("height")}px`;
  const slider = el("input", { type: "range", min: 0, step: 1 });
  const stepLabel = el("span");
  const stepBox = el("label", {}, "step ", slider, stepLabel);
  const camera = el("select", {},
    ...["perspective", "orthographic", "2d"].map((m) => el("option", { value: m, textContent: m })));
  const reset = el("button", { textContent: "reset camera", title: "frame the whole plant (F4)" });
  const play = el("button", { textContent: "pause wind" });
  const status = el("span", { className: "status" });
  const bar = el("div", { className: "bar" }, stepBox, camera, reset, play, status);
  root.append(canvas, bar);
  host.append(root);

  const viewer = new Viewer(canvas, {});
  let first = true, mixer = null, playing = true, last = performance.now(), alive = true;

  function syncControls() {
    const max = model.get("max_steps");
    stepBox.style.display = max > 0 ? "" : "none";
    slider.max = String(max);
    slider.value = String(model.get("step"));
    stepLabel.textContent = `${model.get("step")} / ${max}`;
    camera.value = model.get("camera");
    const msg = model.get("error");
    status.className = msg ? "status error" : "status";
    status.textContent = msg || (model.get("busy") ? "deriving…" : model.get("status"));
    play.style.display = mixer ? "" : "none";
  }

  async function showMesh(kind = "glb") {
    const buffer = arrayBuffer(model.get(kind));
    const t0 = performance.now();
    if (!buffer || buffer.byteLength === 0) {
      // another trait carries the plant now (Python sets the new one first)
      if (["glb", "segments", "lines"].some((k) => arrayBuffer(model.get(k))?.byteLength)) return;
      if (kind !== "glb") return;
      viewer.clear();
    } else if (kind === "lines") {
      viewer.showLines(buffer);  // the preview while a slider is dragged: one-pixel lines
      mixer = null;
      if (first) { viewer.setMode(model.get("camera")); viewer.resetCamera(); first = false; }
    } else if (kind === "segments") {
      viewer.showSegments(buffer);  // the studio Viewer's instanced branches
      mixer = null;
      if (first) { viewer.setMode(model.get("camera")); viewer.resetCamera(); first = false; }
    } else {
      const gltf = await viewer.showGlb(buffer);
      mixer = null;
      if (gltf.animations.length) {
        mixer = new THREE.AnimationMixer(gltf.scene);
        for (const clip of gltf.animations) mixer.clipAction(clip).play();
      }
      if (first) { viewer.setMode(model.get("camera")); viewer.resetCamera(); first = false; }
    }
    viewer._render();  // draw now, so that draw_ms is the time to the new frame
    const ms = performance.now() - t0;
    model.set("draw_ms", ms);
    model.set("shown", viewer.kind || "");
    model.set("frames", model.get("frames") + 1);
    model.save_changes();
    syncControls();
  }

  const tick = (now) => {
    if (!alive) return;
    if (mixer && playing) {
      mixer.update(Math.min(0.1, (now - last) / 1000));
      viewer.invalidate();
    }
    last = now;
    requestAnimationFrame(tick);
  };
  requestAnimationFrame(tick);

  slider.addEventListener("input", () => { stepLabel.textContent = `${slider.value} / ${slider.max}`; });
  slider.addEventListener("change", () => {
    model.set("step", Number(slider.value));
    model.save_changes();
  });
  camera.addEventListener("change", () => {
    viewer.setMode(camera.value);
    viewer.resetCamera();
    model.set("camera", camera.value);
    model.save_changes();
  });
  reset.addEventListener("click", () => viewer.resetCamera());
  canvas.addEventListener("keydown", (e) => { if (e.key === "F4") { e.preventDefault(); viewer.resetCamera(); } });
  play.addEventListener("click", () => {
    playing = !playing;
    play.textContent = playing ? "pause wind" : "play wind";
  });
  model.on("change:glb", () => showMesh("glb"));
  model.on("change:segments", () => showMesh("segments"));
  model.on("change:lines", () => showMesh("lines"));
  for (const name of ["step", "max_steps", "error", "status", "busy"]) {
    model.on(`change:${name}`, syncControls);
  }
  model.on("change:camera", () => {
    if (viewer.mode !== model.get("camera")) { viewer.setMode(model.get("camera")); viewer.resetCamera(); }
    syncControls();
  });
  model.on("change:height", () => { canvas.style.height = `${model.get("height")}px`; viewer.resize(); });
  model.on("msg:custom", (msg) => {
    if (msg && msg.type === "pixels") {
      // a probe for tests: how much of the canvas is not background
      model.send({ type: "pixels", value: drawnFraction(viewer) });
    }
  });
  syncControls();
  await showMesh(arrayBuffer(model.get("segments"))?.byteLength ? "segments" : "glb");
  return () => {
    alive = false;
    viewer._render = () => {};
    viewer._disposePlant();
    viewer.renderer.dispose();
    if (viewer._preview) viewer._preview.dispose();
  };
}

// The fraction of canvas pixels that differ from the background colour.
export function drawnFraction(viewer) {
  viewer._render();
  const gl = viewer.activeRenderer.getContext();
  const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
  const px = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
  const bg = [px[0], px[1], px[2]];
  let differ = 0;
  for (let i = 0; i < px.length; i += 4) {
    if (Math.abs(px[i] - bg[0]) + Math.abs(px[i + 1] - bg[1]) + Math.abs(px[i + 2] - bg[2]) > 24) differ++;
  }
  return differ / (w * h);
}

export default { render };
