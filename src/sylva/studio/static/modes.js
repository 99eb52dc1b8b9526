// Tree mode (a species, every Weber–Penn parameter in grouped documented fields, age and
// wind sliders, growth playback) and World mode (seed, size, the biome map beside the 3D
// view), drawn by the same viewer as the L-systems.
import { checkNumber, markBad, markOk } from "./checks.js";
import { initTexture } from "./texture.js";

const $ = (sel) => document.querySelector(sel);
const $$ = (sel) => Array.from(document.querySelectorAll(sel));

export function initModes(ctx) {
  const { api, app, viewer, message, esc } = ctx;
  const tree = { schema: null, species: null, fields: null, playing: false, pending: null };
  app.tree = tree;
  app.mode = "lsystem";

  function setMode(mode) {
    app.mode = mode;
    document.body.dataset.mode = mode;
    for (const b of $$("[data-mode-button]")) b.classList.toggle("active", b.dataset.modeButton === mode);
    for (const el of $$("[data-mode]")) el.hidden = el.dataset.mode !== mode;
    viewer.clear();
    if (mode === "lsystem") {
      if (app.state) {
        ctx.showState(app.state);  // its background, step and counts in the status bar
        if (app.autoCamera) viewer.setMode(app.state.camera);
        ctx.refresh({ fit: true }).catch(() => {});
      }
    } else {
      viewer.setMode("perspective");
      viewer.setBackground([0.62, 0.78, 0.94]);
      if (mode === "tree") openTree();
      else if (mode === "texture") app.texture.open();
      else if (app.world) drawGrown({ fit: true });
    }
    viewer.resize();
  }
  app.setMode = setMode;
  initTexture(ctx);
  for (const b of $$("[data-mode-button]")) b.onclick = () => setMode(b.dataset.modeButton);

  // ---------------------------------------------------------------- tree
  async function openTree() {
    if (!tree.schema) {
      const r = await api("tree/species");
      if (!r.ok) { message(r.data.message, "error"); return; }
      tree.schema = r.data.schema;
      tree.limits = r.data.limits;
      $("#tree-species").innerHTML = r.data.species.map((s) =>
        `<option value="${esc(s.species)}" title="${esc(s.description)}">${esc(s.name)}</option>`).join("");
      $("#tree-species").value = r.data.species.some((s) => s.species === "black_oak") ? "black_oak" : r.data.species[0].species;
      $("#tree-age").max = tree.limits.age;
      $("#tree-wind").max = tree.limits.wind;
      await pickSpecies();
    } else if (app.grownKind === "tree") {
      await drawGrown({ fit: true });
    } else {
      await growTree({ fit: true });
    }
  }

  async function pickSpecies() {
    const name = $("#tree-species").value;
    const r = await api(`tree/fields?species=${encodeURIComponent(name)}`);
    if (!r.ok) { message(r.data.message, "error"); return; }
    tree.fields = r.data;
    // a young tree first (quick to grow); the slider reaches the species' age
    const age = parseFloat((r.data.blocks.global || {}).Age) || 10;
    $("#tree-age").value = String(Math.min(age, 6));
    $("#tree-age-range").max = String(Math.min(age, Number($("#tree-age").max)));
    $("#tree-age-range").value = $("#tree-age").value;
    buildFields();
    await growTree({ fit: true });
  }
  $("#tree-species").onchange = () => pickSpecies();

  // one field: a text input (numbers may carry a deviation, "13 ± 3"), its range and meaning
  function fieldRow(block, f, value) {
    const range = f.kind === "number" || f.kind === "integer"
      ? `${f.open_lo ? "(" : "["}${f.lo ?? "-∞"}, ${f.hi ?? "∞"}]` : f.kind;
    return `<label title="${esc(f.doc)}">${esc(f.key)}</label>
      <input type="text" data-block="${block}" data-key="${esc(f.key)}" data-kind="${f.kind}"
        ${f.lo != null ? `data-lo="${f.lo}"` : ""} ${f.hi != null ? `data-hi="${f.hi}"` : ""}
        data-open-lo="${f.open_lo ? 1 : 0}" value="${esc(value ?? "")}" placeholder="default">
      <small class="doc">${esc(range)} ${esc(f.doc)}</small>`;
  }

  function buildFields() {
    const b = tree.fields.blocks;
    const levels = Object.keys(b).filter((k) => k.startsWith("level")).sort();
    const parts = [];
    for (const g of tree.schema.global) {
      parts.push(`<details open><summary>${esc(g.group)}</summary><div class="fields">${
        g.keys.map((f) => fieldRow("global", f, (b.global || {})[f.key])).join("")}</div></details>`);
    }
    const nStem = Math.max(1, parseInt((b.global || {}).Levels, 10) || levels.length);
    for (const lv of levels) {
      const n = Number(lv.slice(5));
      const leaves = n >= nStem;
      const keys = leaves ? tree.schema.leaves : tree.schema.level;
      const title = leaves ? `Level ${n}: the leaves` : n === 0 ? "Level 0: the trunk" : `Level ${n}: stems`;
      parts.push(`<details><summary>${title}</summary><div class="fields">${
        keys.map((f) => fieldRow(lv, f, b[lv][f.key])).join("")}</div></details>`);
    }
    $("#tree-fields").innerHTML = parts.join("");
    for (const el of $$("#tree-fields input")) {
      el.addEventListener("input", () => checkField(el));
      el.addEventListener("change", () => { if (checkField(el)) growTree(); });
    }
  }

  // a number field's base value (before any ± deviation) in its range
  function checkField(el) {
    const kind = el.dataset.kind;
    const text = el.value.trim();
    if (text === "" || !(kind === "number" || kind === "integer")) { markOk(el); return true; }
    const m = /^(-?[\d.]+(?:e[-+]?\d+)?)\s*(?:(?:±|\+-)\s*-?[\d.]+)?$/i.exec(text);
    const v = m ? Number(m[1]) : NaN;
    const lo = el.dataset.lo != null ? Number(el.dataset.lo) : -Infinity;
    const hi = el.dataset.hi != null ? Number(el.dataset.hi) : Infinity;
    const open = el.dataset.openLo === "1";
    let ok = Number.isFinite(v) && (open ? v > lo : v >= lo) && v <= hi;
    if (ok && kind === "integer" && !Number.isInteger(v)) ok = false;
    const range = `${open ? "(" : "["}${el.dataset.lo ?? "-inf"}, ${el.dataset.hi ?? "inf"}]`;
    if (!ok) { markBad(el, `expected ${kind === "integer" ? "a whole number" : "a number"} in ${range} (a deviation as 13 ± 3)`); return false; }
    markOk(el);
    return true;
  }

  function blocksOf() {
    const blocks = {};
    for (const el of $$("#tree-fields input")) {
      (blocks[el.dataset.block] ||= {});
      if (el.value.trim() !== "") blocks[el.dataset.block][el.dataset.key] = el.value.trim();
    }
    for (const k of Object.keys(tree.fields.blocks)) blocks[k] ||= {};
    return blocks;
  }

  async function growTree({ fit = false, age = null } = {}) {
    const bad = $$("#tree-fields input").filter((el) => !checkField(el));
    if (bad.length) { message(`${bad[0].dataset.key}: ${bad[0].title}`, "error"); return false; }
    const a = age ?? checkNumber($("#tree-age"));
    const wind = checkNumber($("#tree-wind"));
    const seed = checkNumber($("#tree-seed"));
    if (a === undefined || wind === undefined || seed === undefined) return false;
    if (tree.busy) { tree.pending = { fit, age }; return false; }
    tree.busy = true;
    try {
      const t0 = performance.now();
      const r = await api("tree", { method: "POST", json: { blocks: blocksOf(), extra: tree.fields.extra, age: a, wind, seed } });
      if (!r.ok) {
        const f = r.data && r.data.field;
        const el = f && $(`#tree-fields input[data-block="${f[0]}"][data-key="${f[1]}"]`);
        if (el) { el.closest("details").open = true; markBad(el, r.data.message); }
        else if (r.data && r.data.field) { const e2 = $(`#tree-${r.data.field}`); if (e2) markBad(e2, r.data.message); }
        message(r.data.message, "error");
        return false;
      }
      app.grownKind = "tree";
      app.grown = r.data;
      await drawGrown({ fit });
      const s = r.data.stats;
      $("#st-step").textContent = `Age ${Number(s.age).toFixed(2)} y`;
      $("#st-modules").textContent = `${s.stems.reduce((x, y) => x + y, 0).toLocaleString("en")} stems, ${s.leaves.toLocaleString("en")} leaves`;
      message(`${s.name}: ${s.height.toFixed(2)} m at ${Number(s.age).toFixed(1)} years (grown in ${(performance.now() - t0).toFixed(0)} ms)`);
      return true;
    } finally {
      tree.busy = false;
      if (tree.pending) { const p = tree.pending; tree.pending = null; growTree(p); }
    }
  }
  app.growTree = growTree;

  async function drawGrown({ fit = false } = {}) {
    const r = await api("grown.glb", { raw: true });
    if (!r.ok) { message(r.data.message, "error"); return false; }
    const buf = await r.res.arrayBuffer();
    const t1 = performance.now();
    await viewer.showGlb(buf, { fit });
    app.timing.draw_ms = performance.now() - t1;
    $("#st-triangles").textContent = `${viewer.triangles.toLocaleString("en")} triangles`;
    app.grownDrawn = (app.grownDrawn || 0) + 1;
    return true;
  }

  const ageRange = $("#tree-age-range");
  ageRange.oninput = () => { $("#tree-age").value = ageRange.value; markOk($("#tree-age")); growTree(); };
  $("#tree-age").onchange = () => { const v = checkNumber($("#tree-age")); if (v !== undefined) { ageRange.max = Math.max(Number(ageRange.max), v); ageRange.value = v; growTree(); } };
  $("#tree-wind-range").oninput = () => { $("#tree-wind").value = $("#tree-wind-range").value; markOk($("#tree-wind")); growTree(); };
  $("#tree-wind").onchange = () => { const v = checkNumber($("#tree-wind")); if (v !== undefined) { $("#tree-wind-range").value = v; growTree(); } };
  $("#tree-seed").onchange = () => { if (checkNumber($("#tree-seed")) !== undefined) growTree(); };
  for (const id of ["#tree-age", "#tree-wind", "#tree-seed"]) $(id).addEventListener("input", () => checkNumber($(id)));

  // growth playback: from a seedling to the age in the field, a frame per request
  $("#tree-play").onclick = async () => {
    if (tree.playing) { tree.playing = false; return; }
    const target = checkNumber($("#tree-age"));
    if (target === undefined) return;
    tree.playing = true;
    $("#tree-play").textContent = "Stop";
    try {
      const frames = 12;
      for (let i = 1; i <= frames && tree.playing; i++) {
        const a = Math.max(target * i / frames, 0.05);
        ageRange.value = a;
        if (!(await growTree({ age: a, fit: i === frames }))) break;
      }
    } finally {
      tree.playing = false;
      $("#tree-play").textContent = "Play growth";
    }
  };

  // ---------------------------------------------------------------- world
  $("#world-generate").onclick = async () => {
    const seed = checkNumber($("#world-seed"));
    const size = checkNumber($("#world-size"));
    if (seed === undefined || size === undefined) return;
    message(`Generating a ${size}×${size} world…`);
    $("#world-generate").disabled = true;
    try {
      const r = await api("world", { method: "POST", json: { seed, size, plants: $("#world-plants").checked } });
      if (!r.ok) {
        const el = r.data.field && $(`#world-${r.data.field}`);
        if (el) markBad(el, r.data.message);
        message(r.data.message, "error");
        return;
      }
      app.grownKind = "world";
      app.world = r.data;
      await drawGrown({ fit: true });
      const img = $("#world-biomes");
      const b = await api("world/biomes.png", { raw: true });
      if (b.ok) {
        if (img.src.startsWith("blob:")) URL.revokeObjectURL(img.src);
        img.src = URL.createObjectURL(await b.res.blob());
        img.hidden = false;
      }
      const s = r.data.stats;
      $("#st-step").textContent = `Seed ${s.seed}`;
      $("#st-modules").textContent = `${s.chunks} chunks, ${s.plants.toLocaleString("en")} plants`;
      message(`World ${s.size.join("×")}: ${s.quads.toLocaleString("en")} quads`);
    } finally { $("#world-generate").disabled = false; }
  };
}
