// sylva Studio: wires the editor, the simulation controls, the word view, the 3D canvas, the
// rule-trace debugger, the globals sliders, the help panels, files and exports to the server.
import { checkNumber, markBad, markOk, watch } from "./checks.js";
import { initDebugger } from "./debug.js";
import { Editor, formatNumber } from "./editor.js";
import { initModes } from "./modes.js";
import { Viewer } from "./viewer.js";

const $ = (sel) => document.querySelector(sel);
const $$ = (sel) => Array.from(document.querySelectorAll(sel));
const PAGE = 400;
const NEW_TEXT = "# a new L-system\nrot = 25.7\naxiom = F\n\nF -> F[+F]F[-F]F\n";

const app = {
  info: null,
  state: null,          // the server's last state
  path: null,           // workspace path of the open file, or null
  exampleName: null,    // built-in example the text came from
  dirty: false,
  busy: false,
  stopRequested: false,
  autoCamera: true,
  pageStart: 0,
  picked: null,
  lastTurtle: null,
  constantsKey: "",
  meshStep: null,
  drawnSteps: [],       // the step of every mesh shown, in order (animation)
  lastError: null,
  timing: {},
};
window.studio = app;  // for tests and the console

// ------------------------------------------------------------------------- server
// Each page is its own client.  The server writes a token into its page; with it the page
// opens a session (POST /api/session) and names it in a header on every call, which no
// other site can send.  A session the server released (idle, or a restart) is opened again
// and given the page's last definition and step back, so nothing typed is lost.
const PAGE_TOKEN = document.querySelector('meta[name="sylva-page"]')?.content || "";
let SESSION = null;
let opening = null;
const sleep = (ms) => new Promise((ok) => setTimeout(ok, ms));
const retryAfter = (res) => Math.min(Math.max(Number(res.headers.get("retry-after")) || 5, 1), 30);

async function openSession() {
  for (;;) {
    const res = await fetch("/api/session", {
      method: "POST", body: "{}",
      headers: { "x-sylva-page": PAGE_TOKEN, "content-type": "application/json" },
    });
    if (res.ok) {
      SESSION = (await res.json()).session;
      return SESSION;
    }
    if (res.status !== 503) throw new Error(`the server refused a session (${res.status})`);
    const wait = retryAfter(res);
    message(`The server is full; trying again in ${wait} s`, "error");
    await sleep(wait * 1000);
  }
}

function session() {
  if (!opening) opening = openSession().catch((e) => { opening = null; throw e; });
  return opening;
}

// The session was released: open a new one and load what the page had loaded.
async function reopen() {
  SESSION = null;
  opening = null;
  await session();
  if (app.loadedText != null && app.state) {
    await call("load", { method: "POST",
      json: loadRequest({ text: app.loadedText, steps: app.state.step }) });
  }
}

async function call(path, { method = "GET", json } = {}) {
  const opts = { method, headers: { "x-sylva-session": await session() } };
  if (json !== undefined) {
    opts.body = JSON.stringify(json);
    opts.headers["content-type"] = "application/json";
  }
  return fetch("/api/" + path, opts);
}

async function api(path, { method = "GET", json, raw = false } = {}) {
  let res;
  for (let attempt = 0; ; attempt++) {
    res = await call(path, { method, json });
    if (res.status === 401 && attempt === 0) {
      const data = await res.clone().json().catch(() => null);
      if (data && data.error === "session") { await reopen(); continue; }
    }
    if (res.status === 503 && res.headers.has("retry-after") && attempt < 3) {
      const wait = retryAfter(res);
      message(`The server is busy; trying again in ${wait} s`);
      await sleep(wait * 1000);
      continue;
    }
    break;
  }
  if (raw && res.ok) return { ok: true, status: res.status, res };
  let data = null;
  try { data = await res.json(); } catch { data = { error: "http", message: res.statusText }; }
  return { ok: res.ok, status: res.status, data };
}

app.session = () => SESSION;  // for tests

// the page is closed: its session's work stops and its memory goes at once
window.addEventListener("pagehide", () => {
  if (SESSION) {
    // kept: a page brought back from the history gets 401 and opens a new one
    fetch("/api/session", { method: "DELETE", keepalive: true,
      headers: { "x-sylva-session": SESSION } }).catch(() => {});
  }
});

function message(text, kind = "") {
  const el = $("#st-message");
  el.textContent = text || "";
  el.className = kind;
  const n = $("#notice");
  if (kind === "error" && text) {
    n.textContent = text;
    n.className = "notice error";
    n.hidden = false;
  } else {
    n.hidden = true;
  }
}

// ------------------------------------------------------------------------- editor
const editor = new Editor($("#editor"), {
  onChange: () => { setDirty(true); },
  onCursor: (line, col) => { $("#st-cursor").textContent = `Ln ${line}, Col ${col}`; },
  onRun: () => deriveSteps(),
  onSave: () => save(),
});
app.editor = editor;

function setDirty(d) {
  app.dirty = d;
  const name = app.path || (app.exampleName ? app.exampleName + " (example)" : "untitled");
  $("#title").textContent = name + (d ? " *" : "");
  document.title = `${name}${d ? " *" : ""} — sylva Studio`;
}

function setText(text, { path = null, example = null } = {}) {
  editor.setText(text);
  app.path = path;
  app.exampleName = example;
  setDirty(false);
}

function confirmDiscard() {
  return !app.dirty || window.confirm("The definition has unsaved changes. Discard them?");
}

// ------------------------------------------------------------------------- viewer
const viewer = new Viewer($("#view"), {
  onPick: (point) => pick(point),
  onCamera: (cam) => showCamera(cam),
});
app.viewer = viewer;

function showCamera(cam) {
  const f = (v) => v.map((x) => x.toFixed(3)).join(", ");
  const names = { perspective: "3D perspective", orthographic: "3D orthogonal", "2d": "2D" };
  $("#cam-mode").textContent = names[cam.mode];
  $("#cam-target").textContent = f(cam.target);
  $("#cam-rotx").textContent = cam.pitch.toFixed(1) + "°";
  $("#cam-roty").textContent = cam.yaw.toFixed(1) + "°";
  $("#cam-dist").textContent = `${cam.distance.toFixed(3)} (zoom ${cam.zoom.toFixed(0)})`;
  $("#cam-pos").textContent = f(cam.position);
  $("#st-camera").textContent = names[cam.mode] + (app.autoCamera ? " (auto)" : "");
  for (const r of $$("input[name=camera-mode]")) r.checked = r.value === cam.mode;
}

function setCameraMode(mode, { manual = true } = {}) {
  if (manual && mode === viewer.mode) return;
  viewer.setMode(mode);
  viewer.resetCamera();
}

// ------------------------------------------------------------------------- state display
function showState(s) {
  app.state = s;
  $("#derived-steps").textContent = s.step;
  $("#st-step").textContent = `Step ${s.step}`;
  $("#st-modules").textContent = `${s.modules.toLocaleString("en")} modules`;
  $("#word-length").textContent = s.modules.toLocaleString("en");
  viewer.setBackground(s.background);
  if (s.turtle !== app.lastTurtle) loadHelp(s.turtle);
  // rebuild the sliders when the program's globals change; when only their values do (the
  // text was edited, or a slider moved), the sliders follow in place
  const key = JSON.stringify(Object.keys(s.constants));
  if (key !== app.constantsKey) buildGlobals(s.constants);
  else updateGlobals(s.constants);
  app.constantsKey = key;
  for (const f of ctx.onState) f(s);
  showTiming();
}

function showTiming() {
  const t = app.state ? app.state.timings || {} : {};
  const parts = [];
  if (t.derive_ms != null) parts.push(`derive ${t.derive_ms.toFixed(0)} ms`);
  if (app.timing.mesh_ms != null) parts.push(`mesh ${app.timing.mesh_ms.toFixed(0)} ms`);
  if (app.timing.draw_ms != null) parts.push(`draw ${app.timing.draw_ms.toFixed(0)} ms`);
  $("#st-timing").textContent = parts.join(" · ");
  $("#st-triangles").textContent = viewer.kind === "preview"
    ? `preview: ${viewer.lines.toLocaleString("en")} branches as lines`
    : `${viewer.triangles.toLocaleString("en")} triangles`;
}

async function drawMesh({ fit = false } = {}) {
  if (app.mode && app.mode !== "lsystem") return false;  // Tree and World modes draw their own
  const t0 = performance.now();
  const r = await api("mesh?instanced=1", { raw: true });
  if (!r.ok) { showError(r.data); return false; }
  app.timing.mesh_ms = Number(r.res.headers.get("x-sylva-mesh-ms"));
  const buf = await r.res.arrayBuffer();
  const t1 = performance.now();
  app.meshKind = r.res.headers.get("x-sylva-kind") || "glb";
  if (app.meshKind === "segments") viewer.showSegments(buf, { fit });
  else await viewer.showGlb(buf, { fit });
  app.timing.draw_ms = performance.now() - t1;
  app.timing.roundtrip_ms = t1 - t0;
  app.timing.mesh_bytes = buf.byteLength;
  app.meshShownAt = performance.now();
  app.meshStep = Number(r.res.headers.get("x-sylva-step"));
  app.drawnSteps.push(app.meshStep);
  if (app.picked) {
    app.picked = null;
    $("#trace-box").innerHTML = '<p class="muted">Click a branch in the view to see the module that drew it and the rule and step that made it.</p>';
  }
  showTiming();
  return true;
}

async function refresh({ fit = false } = {}) {
  await Promise.all([drawMesh({ fit }), showWordPage(lastPageStart())]);
}

function lastPageStart() {
  const n = app.state ? app.state.modules : 0;
  return Math.min(app.pageStart, Math.max(0, Math.floor((n - 1) / PAGE) * PAGE));
}

// An error answer of the server: a syntax error gets an editor marker.
function showError(data) {
  app.lastError = data;
  if (!data) return;
  if (data.error === "syntax") {
    editor.showError(data.line, data.column, data.message);
    $("#error-box").textContent = data.detail || data.message;
    $("#error-box").hidden = false;
    message(`Line ${data.line}, column ${data.column}: ${data.message}`, "error");
  } else {
    message(data.message || "error", "error");
  }
  if (data.state) showState(data.state);
}

function clearError() {
  app.lastError = null;
  $("#error-box").hidden = true;
  message("");
}

// ------------------------------------------------------------------------- simulation
function setBusy(b, total = 0) {
  app.busy = b;
  $("#btn-stop").disabled = !b;
  for (const id of ["#btn-derive", "#btn-reset", "#btn-step", "#btn-back"]) $(id).disabled = b;
  const p = $("#progress");
  p.max = Math.max(total, 1);
  p.value = 0;
  clearInterval(app.progressTimer);
  $("#st-progress").textContent = "";
  if (b) app.progressTimer = setInterval(pollProgress, 250);
}

// Seed 001's two figures during long work: steps derived and modules interpreted.
async function pollProgress() {
  if (!app.busy || app.polling) return;
  app.polling = true;
  try {
    const r = await api("progress");
    if (!r.ok || !app.busy) return;
    const g = r.data;
    const parts = [];
    if (g.of) parts.push(`${g.steps} of ${g.of} steps derived`);
    if (g.interpreting) parts.push(`${(g.interpreted || 0).toLocaleString("en")} of ${g.interpreting.toLocaleString("en")} modules interpreted`);
    $("#st-progress").textContent = parts.join(" · ");
    if (g.of) $("#progress").value = Math.max($("#progress").value, g.steps);
    app.progress = g;
  } finally { app.polling = false; }
}

function loadRequest(extra = {}) {
  const seedText = $("#seed").value.trim();
  const body = {
    text: editor.text,
    dialect: $("#dialect").value || null,
    filename: app.path || (app.exampleName ? app.info.examples.find((e) => e.name === app.exampleName)?.file : null),
    trace: $("#trace").checked,
    overrides: app.overrides || {},
    ...extra,
  };
  if (seedText !== "") body.seed = checkNumber($("#seed"));
  return body;
}

// Reset simulation: parse and load the definition; the axiom becomes the current word.
async function resetSimulation({ keepOverrides = false } = {}) {
  // the sliders' values hold for the text they were set on; an edit starts afresh
  if (!keepOverrides || editor.text !== app.loadedText) app.overrides = {};
  const req = loadRequest();
  if ("seed" in req && req.seed === undefined) { message(`Seed: ${$("#seed").title}`, "error"); return false; }
  const r = await api("load", { method: "POST", json: req });
  if (!r.ok) { showError(r.data); return false; }
  clearError();
  app.loadedText = editor.text;
  app.overrides = r.data.overrides;
  showState(r.data);
  if (app.autoCamera) {
    viewer.setMode(r.data.camera);
    showCamera(viewer.cameraState());
  }
  app.pageStart = 0;
  return true;
}

async function deriveSteps() {
  if (app.busy) return;
  const total = checkNumber($("#steps"));
  const animate = $("#animate").checked;
  const every = checkNumber($("#every"));
  const frameMs = checkNumber($("#frame-ms"));
  if (total === undefined || every === undefined || frameMs === undefined) {
    message("A field of the simulation is out of its range (in red)", "error");
    return;
  }
  app.stopRequested = false;
  setBusy(true, total);
  try {
    if (!(await resetSimulation({ keepOverrides: true }))) return;
    let done = 0;
    let first = true;
    if (animate) { await refresh({ fit: true }); first = false; }
    while (done < total && !app.stopRequested) {
      const n = animate ? Math.min(every, total - done) : total - done;
      const t0 = performance.now();
      const r = await api("step", { method: "POST", json: { n } });
      if (!r.ok) {
        showError(r.data);
        if (r.data && r.data.state) await refresh({ fit: first });
        return;
      }
      showState(r.data);
      done += n;
      $("#progress").value = done;
      if (animate || done >= total) {
        await refresh({ fit: first });
        first = false;
        const wait = frameMs - (performance.now() - t0);
        if (animate && done < total && wait > 0) await new Promise((ok) => setTimeout(ok, wait));
      }
    }
    if (first) await refresh({ fit: true });
    message(app.stopRequested ? `Stopped at step ${app.state.step}` : `Derived ${app.state.step} steps`);
  } finally {
    setBusy(false);
  }
}

async function simpleAction(path, json) {
  if (app.busy) return;
  if (!app.state) { if (!(await resetSimulation())) return; }
  setBusy(true, 1);
  try {
    const r = await api(path, { method: "POST", json: json || {} });
    if (!r.ok) { showError(r.data); if (r.data && r.data.state) await refresh(); return; }
    clearError();
    showState(r.data);
    $("#progress").value = 1;
    await refresh({ fit: app.meshStep === null });
  } finally {
    setBusy(false);
  }
}

async function resetAction() {
  if (app.busy) return;
  setBusy(true, 1);
  try {
    if (await resetSimulation({ keepOverrides: true })) await refresh({ fit: true });
  } finally { setBusy(false); }
}

async function stop() {
  app.stopRequested = true;
  await api("stop", { method: "POST", json: {} });
}

// ------------------------------------------------------------------------- word view
async function showWordPage(start) {
  if (!app.state) return;
  const n = app.state.modules;
  start = Math.max(0, Math.min(start, Math.max(0, Math.floor((n - 1) / PAGE) * PAGE)));
  const r = await api(`word?start=${start}&count=${PAGE}`);
  if (!r.ok) return;
  app.pageStart = r.data.start;
  const box = $("#word");
  box.textContent = "";
  const frag = document.createDocumentFragment();
  r.data.modules.forEach((m, k) => {
    const s = document.createElement("span");
    const i = r.data.start + k;
    s.textContent = m;
    s.dataset.i = i;
    s.className = moduleClass(m) + (app.picked && app.picked.index === i ? " hl" : "");
    frag.appendChild(s);
  });
  box.appendChild(frag);
  const pages = Math.max(1, Math.ceil(n / PAGE));
  $("#page-info").textContent = `${Math.floor(r.data.start / PAGE) + 1} / ${pages}`;
  const hl = box.querySelector(".hl");
  if (hl) hl.scrollIntoView({ block: "nearest" });
}

// word highlighting: branches, turtle commands and the other modules apart
function moduleClass(m) {
  const c = m[0];
  if (c === "[" || c === "]") return "m-branch";
  if ("+-^&\\/|$!~;_{}.%'".includes(c)) return "m-turtle";
  return m.includes("(") ? "m-param" : "m-symbol";
}

$("#page-first").onclick = () => showWordPage(0);
$("#page-prev").onclick = () => showWordPage(app.pageStart - PAGE);
$("#page-next").onclick = () => showWordPage(app.pageStart + PAGE);
$("#page-last").onclick = () => showWordPage(Number.MAX_SAFE_INTEGER);

// ------------------------------------------------------------------------- rule trace
// A click on the canvas: the module that drew the branch there.
async function pick(point) {
  if (!app.state) return;
  const r = await api("pick", { method: "POST", json: { point } });
  if (!r.ok) { message(r.data.message, "error"); return; }
  await showTrace(r.data, point);
}

// A click on a module of the word: what it drew.
async function traceModule(index) {
  if (!app.state) return;
  const r = await api(`module?index=${index}`);
  if (!r.ok) { message(r.data.message, "error"); return; }
  await showTrace(r.data, null);
}

async function showTrace(p, point) {
  app.picked = p;
  if (p.segment) viewer.highlightSegment(p.segment);
  else if (point) viewer.highlightPoint(point);
  else viewer.clearHighlight();
  const box = $("#trace-box");
  let rule = `<dd class="rule">the axiom</dd>`;
  if (p.rule === undefined) rule = `<dd class="rule muted">(rule tracing is off)</dd>`;
  else if (p.rule) {
    const where = p.rule.line != null ? ` <span class="muted">(line ${p.rule.line}, column ${p.rule.column})</span>` : "";
    rule = `<dd class="rule"><a href="#" id="goto-rule">${esc(p.rule.text)}</a>${where}</dd>`;
  }
  const drew = p.kind ? esc(p.kind) + (p.render_index !== p.index ? ` (render word module ${p.render_index})` : "")
    : "nothing";
  box.innerHTML = `<dl>
    <dt>Module</dt><dd class="module">${esc(p.module)}</dd>
    <dt>Index in word</dt><dd class="index">${p.index}</dd>
    <dt>Drew</dt><dd class="drew">${drew}</dd>
    <dt>Made by</dt>${rule}
    <dt>In step</dt><dd class="made-step">${p.made_at_step ?? "?"}</dd>
  </dl>`;
  const a = $("#goto-rule");
  if (a && p.rule.line != null) a.onclick = (e) => { e.preventDefault(); editor.goTo(p.rule.line, p.rule.column); };
  await showWordPage(Math.floor(p.index / PAGE) * PAGE);
  message(`Picked ${p.module} (module ${p.index})`);
}

$("#word").addEventListener("click", (e) => {
  const span = e.target.closest("span[data-i]");
  if (span) traceModule(Number(span.dataset.i));
});

function esc(s) {
  return String(s).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" }[c]));
}

// ------------------------------------------------------------------------- globals sliders
// A slider (or its number field) sets the number in the text, as one undoable edit, and the
// plant is derived again to the same step; editing the number in the text moves the slider
// when the text is derived.  A global the text computes (no plain number) is overridden.
function sliderRange(v) {
  const lo = v === 0 ? -1 : Math.min(0, 2 * v), hi = v === 0 ? 1 : Math.max(2 * v, 0);
  return [lo, hi];
}

function buildGlobals(constants) {
  const box = $("#globals");
  box.textContent = "";
  const names = Object.keys(constants);
  if (!names.length) { box.innerHTML = '<p class="muted">No numeric globals.</p>'; return; }
  for (const name of names) {
    const v = constants[name];
    const [lo, hi] = sliderRange(v);
    const row = document.createElement("div");
    row.className = "row";
    row.innerHTML = `<label>${esc(name)}</label>
      <input type="range" min="${lo}" max="${hi}" step="${(hi - lo) / 200}" value="${v}" data-global="${esc(name)}">
      <input type="number" step="any" value="${v}" data-global-number="${esc(name)}">`;
    box.appendChild(row);
    const range = row.querySelector("input[type=range]");
    const num = row.querySelector("input[type=number]");
    const changed = (value, drag = false) => {
      app.changedAt = performance.now();
      if (editor.setNumber(name, value)) {
        const { [name]: _, ...rest } = app.overrides || {};
        app.overrides = rest;
      } else {
        app.overrides = { ...(app.overrides || {}), [name]: value };
      }
      if (drag && usePreview()) {
        // a large plant while the slider moves: its lines now, the full frame when the
        // slider is let go (or rests)
        preview();
        clearTimeout(app.settleTimer);
        app.settleTimer = setTimeout(settle, app.settleMs);
      } else {
        rerun();
      }
    };
    range.oninput = () => { num.value = formatNumber(Number(range.value)); markOk(num); changed(Number(num.value), true); };
    range.onchange = () => { if (app.settleTimer) settle(); };  // let go: the full frame now
    num.oninput = () => {
      const t = num.value.trim();
      if (t === "" || !Number.isFinite(Number(t))) markBad(num, "expected a finite number");
      else markOk(num);
    };
    num.onchange = () => {
      const x = Number(num.value);
      if (num.value.trim() === "" || !Number.isFinite(x)) { markBad(num, "expected a finite number"); return; }
      markOk(num);
      if (x < Number(range.min) || x > Number(range.max)) {
        const [a, b] = sliderRange(x);
        range.min = Math.min(a, Number(range.min));
        range.max = Math.max(b, Number(range.max));
        range.step = (range.max - range.min) / 200;
      }
      range.value = x;
      changed(x);
    };
  }
}

// The values of the text, derived: the sliders follow unless one is being moved.
function updateGlobals(constants) {
  for (const [name, v] of Object.entries(constants)) {
    const range = document.querySelector(`input[data-global="${CSS.escape(name)}"]`);
    const num = document.querySelector(`input[data-global-number="${CSS.escape(name)}"]`);
    if (!range || !num || document.activeElement === range || document.activeElement === num) continue;
    if (Math.abs(Number(num.value) - v) <= 1e-9 * Math.max(1, Math.abs(v))) continue;
    if (v < Number(range.min) || v > Number(range.max)) {
      const [lo, hi] = sliderRange(v);
      range.min = lo; range.max = hi; range.step = (hi - lo) / 200;
    }
    range.value = v;
    num.value = formatNumber(v);
    markOk(num);
  }
}

// Re-run to the current step with the sliders' values.
// A change while one is being derived waits for it and then runs once with the latest
// values (the changes in between are coalesced).
async function rerun() {
  if (app.busy) { app.rerunPending = true; return; }
  app.rerunPending = false;
  const steps = app.state ? app.state.step : 0;
  setBusy(true, steps);
  const t0 = performance.now();
  try {
    const r = await api("load", { method: "POST", json: loadRequest({ steps }) });
    app.timing.load_ms = performance.now() - t0;
    if (!r.ok) { showError(r.data); if (r.data.state) await refresh(); return; }
    clearError();
    app.loadedText = editor.text;
    showState(r.data);
    await refresh();
  } finally {
    setBusy(false);
    if (app.rerunPending) rerun();
    else if (app.previewPending) preview();
  }
}

// ------------------------------------------------------------------------- preview
// While a slider of a large plant is dragged, each change is derived on the server and
// answered with the branches as lines (POST /api/preview: one round trip, a compact
// binary of end points and colours, no mesh built), drawn as one-pixel lines; when the
// slider is let go, or rests for app.settleMs, the same request is loaded again (the
// server keeps what it derived) and the full frame replaces the lines.
const PREVIEW_FROM = 100_000;  // triangles of the frame shown from which a drag previews
app.previewFrom = PREVIEW_FROM;  // tests lower it
app.settleMs = 300;
app.previews = 0;                // previews drawn (tests)

function usePreview() {
  if (app.mode && app.mode !== "lsystem") return false;
  return viewer.kind === "preview" || viewer.triangles >= app.previewFrom;
}

function settle() {
  clearTimeout(app.settleTimer);
  app.settleTimer = null;
  if (app.previewing || app.previewPending) { app.settleWanted = true; return; }
  rerun();
}

async function preview() {
  if (app.busy || app.previewing) { app.previewPending = true; return; }
  app.previewPending = false;
  app.previewing = true;
  const steps = app.state ? app.state.step : 0;
  const t0 = performance.now();
  try {
    const r = await api("preview", { method: "POST", json: loadRequest({ steps }), raw: true });
    if (!r.ok) {
      if (r.data && r.data.error !== "superseded") showError(r.data);
      return;
    }
    const buf = await r.res.arrayBuffer();
    const t1 = performance.now();
    if (!buf.byteLength) return;  // no branches (polygons only): the frame before stays
    viewer.showLines(buf);
    app.previewShownAt = performance.now();
    viewer._render();  // now, not at the next animation frame
    viewer.renderedAt = performance.now();
    const h = (k) => Number(r.res.headers.get("x-sylva-" + k));
    app.timing.preview = {
      derive_ms: h("derive-ms"), turtle_ms: h("turtle-ms"), lines_ms: h("lines-ms"),
      roundtrip_ms: t1 - t0, upload_ms: app.previewShownAt - t1, bytes: buf.byteLength,
      step: h("step"), modules: h("modules"),
    };
    app.previews += 1;
    clearError();
    showTiming();
  } finally {
    app.previewing = false;
    if (app.previewPending) preview();
    else if (app.settleWanted) { app.settleWanted = false; rerun(); }
  }
}

// ------------------------------------------------------------------------- help
async function loadHelp(turtle) {
  app.lastTurtle = turtle;
  const r = await api(`help?turtle=${encodeURIComponent(turtle)}`);
  if (!r.ok) return;
  $("#help-symbols tbody").innerHTML = r.data.symbols
    .map((s) => `<tr><td>${esc(s.symbol)}</td><td>${esc(s.meaning)}</td></tr>`).join("");
  $("#help-vars tbody").innerHTML = r.data.variables
    .map((v) => `<tr><td>${esc(v.name)}</td><td>${esc(v.default)}</td><td>${esc(v.meaning)}</td></tr>`).join("");
}

// ------------------------------------------------------------------------- files
async function openDialog() {
  if (!confirmDiscard()) return;
  const files = await api("files");
  const sel = $("#open-files");
  sel.innerHTML = (files.ok ? files.data.files : [])
    .map((f) => `<option value="${esc(f.path)}">${esc(f.path)}</option>`).join("");
  const ex = $("#open-examples");
  ex.innerHTML = app.info.examples
    .map((e) => `<option value="${esc(e.name)}">${esc(e.name)} — ${esc(e.title)}</option>`).join("");
  sel.onchange = () => { ex.selectedIndex = -1; };
  ex.onchange = () => { sel.selectedIndex = -1; };
  const dlg = $("#dlg-open");
  dlg.returnValue = "";
  dlg.showModal();
  dlg.onclose = async () => {
    if (dlg.returnValue !== "ok") return;
    if (sel.value) await openFile(sel.value);
    else if (ex.value) await openExample(ex.value);
  };
}

async function openFile(path) {
  const r = await api(`file?path=${encodeURIComponent(path)}`);
  if (!r.ok) { message(r.data.message, "error"); return false; }
  setText(r.data.text, { path: r.data.path });
  await afterOpen();
  return true;
}

async function openExample(name) {
  const r = await api(`example?name=${encodeURIComponent(name)}`);
  if (!r.ok) { message(r.data.message, "error"); return false; }
  setText(r.data.text, { example: name });
  await afterOpen();
  return true;
}

async function afterOpen() {
  app.overrides = {};
  app.constantsKey = "";
  viewer.clear();
  const ok = await resetSimulation();
  if (ok && app.state.steps_hint != null) $("#steps").value = app.state.steps_hint;
  if (ok) await deriveSteps();
}

async function save() {
  if (!app.path) return saveAs();
  return writeFile(app.path, true);
}

async function writeFile(path, overwrite) {
  const r = await api("file", { method: "PUT", json: { path, text: editor.text, overwrite } });
  if (!r.ok) {
    if (r.status === 409 && !overwrite && window.confirm(`${path} exists. Replace it?`)) {
      return writeFile(path, true);
    }
    message(r.data.message, "error");
    return false;
  }
  app.path = r.data.path;
  app.exampleName = null;
  setDirty(false);
  message(`Saved ${r.data.path}`);
  return true;
}

function saveAs() {
  const dlg = $("#dlg-save");
  $("#save-path").value = app.path || (app.exampleName ? app.exampleName + ".lsys" : "untitled.lsys");
  dlg.returnValue = "";
  dlg.showModal();
  return new Promise((resolve) => {
    dlg.onclose = async () => {
      resolve(dlg.returnValue === "ok" ? await writeFile($("#save-path").value.trim(), false) : false);
    };
  });
}

function newFile() {
  if (!confirmDiscard()) return;
  setText(NEW_TEXT);
  viewer.clear();
  app.state = null;
}

// ------------------------------------------------------------------------- exports
function download(blob, name) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.appendChild(a);
  a.click();
  setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
}

function filenameOf(res, fallback) {
  const m = /filename="([^"]+)"/.exec(res.headers.get("content-disposition") || "");
  return m ? m[1] : fallback;
}

// What the exports write: the L-system, or the tree or world of those modes.
function exportOf() {
  if (app.mode === "texture") return null;
  if (app.mode === "tree" || app.mode === "world") return app.grownKind === app.mode ? app.mode : null;
  return app.state ? "lsystem" : null;
}

function nothingToExport() {
  if (app.mode === "texture") return "Texture mode saves its image with Save TOML + PNG";
  return app.mode === "lsystem" ? "Derive an L-system first" : `Grow a ${app.mode} first`;
}

async function exportMesh(fmt) {
  const of = exportOf();
  if (!of) { message(nothingToExport(), "error"); return; }
  const r = await api(`export.${fmt}?of=${of}`, { raw: true });
  if (!r.ok) { message(r.data.message, "error"); return; }
  download(await r.res.blob(), filenameOf(r.res, `plant.${fmt}`));
  message(`Exported ${fmt.toUpperCase()}`);
}

function exportImageDialog() {
  if (!exportOf()) { message(nothingToExport(), "error"); return; }
  const dlg = $("#dlg-export");
  $("#export-focus").checked = $("#opt-focus").checked;
  dlg.returnValue = "";
  dlg.showModal();
  dlg.onclose = async () => {
    if (dlg.returnValue !== "ok") return;
    await exportImage(Number($("#export-w").value), Number($("#export-h").value), $("#export-focus").checked,
      $("#export-format").value);
  };
}
// the size fields refuse a bad value in place; the dialog stays open
$("#export-ok").addEventListener("click", (e) => {
  const w = checkNumber($("#export-w")), h = checkNumber($("#export-h"));
  if (w === undefined || h === undefined) e.preventDefault();
});

async function exportImage(width, height, focus, format = "png") {
  message(`Rendering ${width}×${height}…`);
  const r = await api("export-png", { method: "POST", raw: true,
    json: { width, height, focus, format, of: exportOf(), camera: viewer.cameraState() } });
  if (!r.ok) { message(r.data.message, "error"); return null; }
  const blob = await r.res.blob();
  download(blob, filenameOf(r.res, `plant.${format}`));
  message(`Exported a ${width}×${height} ${format.toUpperCase()}`);
  return blob;
}
app.exportImage = exportImage;

// ------------------------------------------------------------------------- menus, docks
const actions = {
  new: newFile, open: openDialog, "save-as": saveAs,
  save: () => (app.mode === "texture" ? app.texture.save() : save()),
  "export-image": exportImageDialog, "export-scad": () => exportMesh("scad"),
  derive: deriveSteps, reset: resetAction, step: () => simpleAction("step", { n: 1 }),
  back: () => simpleAction("back"), stop,
  "reset-camera": () => viewer.resetCamera(),
  about: () => $("#dlg-about").showModal(),
};
// every mesh format of sylva.geometry.exchange, from the server's list
const FORMAT_NAMES = { glb: "GLB (binary glTF)", gltf: "glTF", obj: "OBJ", ply: "PLY", stl: "STL",
  pov: "POV-Ray", svg: "SVG", usd: "USD", usda: "USDA", usdc: "USDC" };
function exportMenu(formats) {
  $("#export-formats").innerHTML = formats.filter((f) => f !== "scad")
    .map((f) => `<button data-action="export-${f}">Export ${esc(FORMAT_NAMES[f] || f.toUpperCase())}</button>`).join("");
  for (const f of formats) actions[`export-${f}`] ||= () => exportMesh(f);
  bindActions($("#export-formats"));
}
function bindActions(root) {
  for (const el of root.querySelectorAll("[data-action]")) {
    el.addEventListener("click", () => {
      for (const m of $$(".menu.open")) m.classList.remove("open");
      actions[el.dataset.action]();
    });
  }
}
bindActions(document);
for (const m of $$(".menu")) {
  m.querySelector(".menu-title").addEventListener("click", (e) => {
    e.stopPropagation();
    const open = m.classList.contains("open");
    for (const o of $$(".menu.open")) o.classList.remove("open");
    if (!open) m.classList.add("open");
  });
}
document.addEventListener("click", (e) => {
  if (!e.target.closest(".menu-items label")) for (const m of $$(".menu.open")) m.classList.remove("open");
});

// Window menu: one toggle per dock; each dock has a close button.
for (const dock of $$(".dock")) {
  const label = document.createElement("label");
  label.innerHTML = `<input type="checkbox" data-dock-toggle="${dock.id}"> ${esc(dock.dataset.title)}`;
  $("#window-items").appendChild(label);
  const close = document.createElement("button");
  close.className = "close";
  close.title = "Close";
  close.textContent = "×";
  close.onclick = () => setDock(dock.id, false);
  dock.querySelector("h2").appendChild(close);
}
function setDock(id, on) {
  $("#" + id).hidden = !on;
  for (const t of $$(`[data-dock-toggle="${id}"]`)) t.checked = on;
  viewer.resize();
}
for (const t of $$("[data-dock-toggle]")) {
  t.checked = !$("#" + t.dataset.dockToggle).hidden;
  t.addEventListener("change", () => setDock(t.dataset.dockToggle, t.checked));
}

$("#opt-focus").addEventListener("change", (e) => viewer.setFocusVisible(e.target.checked));
$("#opt-auto-camera").addEventListener("change", (e) => {
  app.autoCamera = e.target.checked;
  showCamera(viewer.cameraState());
});
for (const r of $$("input[name=camera-mode]")) {
  r.addEventListener("change", () => { if (r.checked) setCameraMode(r.value); });
}
document.addEventListener("keydown", (e) => {
  if (e.key === "F4") { e.preventDefault(); viewer.resetCamera(); }
  if ((e.ctrlKey || e.metaKey) && e.key === "s" && !e.defaultPrevented) { e.preventDefault(); actions.save(); }
  if ((e.ctrlKey || e.metaKey) && e.key === "Enter" && !e.defaultPrevented) { e.preventDefault(); deriveSteps(); }
});
window.addEventListener("beforeunload", (e) => {
  if (app.dirty) { e.preventDefault(); e.returnValue = ""; }
});

// ------------------------------------------------------------------------- start
// what the debugger and the modes use of this page
const ctx = {
  api, app, viewer, editor, message, esc, onState: [],
  refresh: (o) => refresh(o), showState: (x) => showState(x), showError: (d) => showError(d),
  clearError: () => clearError(), setBusy: (b, t) => setBusy(b, t),
  resetSimulation: (o) => resetSimulation(o), traceModule: (i) => traceModule(i),
};
for (const id of ["#steps", "#every", "#frame-ms", "#export-w", "#export-h"]) watch($(id));
watch($("#seed"), { optional: true });
initDebugger(ctx);
initModes(ctx);

async function start() {
  const r = await api("info");
  app.info = r.data;
  exportMenu(app.info.export_formats || ["glb", "obj", "scad"]);
  await loadHelp("lsys");
  showCamera(viewer.cameraState());
  const sf = app.info.start_file;
  let opened = false;
  if (sf && sf.startsWith("file:")) opened = await openFile(sf.slice(5));
  else if (sf && sf.startsWith("example:")) opened = await openExample(sf.slice(8));
  if (!opened) { setText(NEW_TEXT); setDirty(false); }
  app.ready = true;
  document.body.dataset.ready = "1";
}
start();
