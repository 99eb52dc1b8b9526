// Texture mode (issue 22): a texture graph's TOML in an editor, its image rendered by the
// server's CPU graph kernel (small while editing), a bad text marked at the line and column
// the graph loader names, the graph's nodes as a tree from its output, and a save of the
// TOML and its full-size PNG together.
import { Editor, tomlLanguage } from "./editor.js";

const $ = (sel) => document.querySelector(sel);
const DEFAULT_PRESET = "arabescato-marble";

export function initTexture(ctx) {
  const { api, app, message, esc } = ctx;
  const tex = { opened: false, shown: 0, seq: 0, timer: null, busy: false, last: null, error: null };
  app.texture = tex;

  const editor = new Editor($("#tex-editor"), {
    language: tomlLanguage,
    onChange: () => {
      $("#tex-error").hidden = true;
      if ($("#tex-live").checked) schedule();
    },
    onCursor: (ln, col) => { $("#st-cursor").textContent = `Ln ${ln}, Col ${col}`; },
    onRun: () => render(),
    onSave: () => save(),
  });
  tex.editor = editor;

  function schedule() {
    clearTimeout(tex.timer);
    tex.timer = setTimeout(() => render(), 250);
  }

  function showError(data) {
    tex.error = data;
    const box = $("#tex-error");
    box.textContent = data.message;
    box.hidden = false;
    if (data.line) editor.showError(data.line, data.column || 1, data.detail || data.message);
    message(data.message.split("\n")[0], "error");
  }

  // the graph's nodes as a tree from its output: each input's slot, the node feeding it
  // (or its number) and the node's parameters
  function showNodes(nodes) {
    const byName = Object.fromEntries(nodes.map((n) => [n.name, n]));
    const params = (n) => Object.entries(n.params).map(([k, v]) =>
      `${esc(k)}=${esc(typeof v === "object" ? JSON.stringify(v) : v)}`).join(", ");
    const item = (n, slot, depth) => {
      const head = `${slot ? `<span class="slot">${esc(slot)} ←</span> ` : ""}<span class="name">${esc(n.name)}</span>: ` +
        `<span class="type" title="${esc(n.category)}">${esc(n.type)}</span> <span class="params">${params(n)}</span>`;
      const kids = depth > 32 ? [] : Object.entries(n.inputs).map(([k, v]) =>
        (typeof v === "string" && byName[v]) ? item(byName[v], k, depth + 1)
          : `<li><span class="slot">${esc(k)} ←</span> ${esc(v)}</li>`);
      return `<li data-node="${esc(n.name)}">${head}${kids.length ? `<ul>${kids.join("")}</ul>` : ""}</li>`;
    };
    const out = nodes[nodes.length - 1];
    $("#tex-nodes").innerHTML = out ? `<ul>${item(out, "", 0)}</ul>` : "";
  }

  async function render({ side } = {}) {
    clearTimeout(tex.timer);
    const seq = ++tex.seq;
    const text = editor.text;
    tex.busy = true;
    try {
      const r = await api("texture", { method: "POST", json: { text, ...(side != null ? { side } : {}) } });
      if (seq !== tex.seq) return false;  // a newer text is on its way
      if (!r.ok) {
        if (r.status === 409 && r.data.error === "superseded") return false;
        showError(r.data);
        return false;
      }
      tex.error = null;
      editor.clearError();
      $("#tex-error").hidden = true;
      const d = r.data;
      const img = $("#tex-image");
      await new Promise((ok) => {
        img.onload = ok;
        img.onerror = ok;
        img.src = `data:image/png;base64,${d.png}`;
      });
      // small images are shown larger, pixel for pixel
      const k = Math.max(1, Math.floor(256 / Math.max(d.width, d.height)));
      img.style.width = `${d.width * k}px`;
      img.style.height = `${d.height * k}px`;
      $("#tex-caption").textContent = `${d.width}×${d.height} preview of a ${d.size.join("×")} ${d.output} graph · ${d.nodes.length} node${d.nodes.length === 1 ? "" : "s"} · ${d.ms.toFixed(0)} ms`;
      showNodes(d.nodes);
      tex.last = d;
      tex.shown++;
      message(`Rendered in ${d.ms.toFixed(0)} ms`);
      return true;
    } finally {
      if (seq === tex.seq) tex.busy = false;
    }
  }
  tex.render = render;

  async function pickPreset(name) {
    const r = await api(`texture/preset?name=${encodeURIComponent(name)}`);
    if (!r.ok) { message(r.data.message, "error"); return false; }
    $("#tex-path").value = `${name}.toml`;
    editor.setText(r.data.text);  // onChange schedules a render when Live is on
    if (!$("#tex-live").checked) return render();
    return true;
  }

  async function listFiles() {
    const r = await api("texture/files");
    if (!r.ok) return;
    $("#tex-files").innerHTML = `<option value="">—</option>` + r.data.files.map((f) =>
      `<option value="${esc(f.path)}">${esc(f.path)}</option>`).join("");
  }

  async function openFile(path) {
    const r = await api(`texture/file?path=${encodeURIComponent(path)}`);
    if (!r.ok) { message(r.data.message, "error"); return false; }
    $("#tex-path").value = path;
    editor.setText(r.data.text);
    if (!$("#tex-live").checked) await render();
    return true;
  }

  async function save(overwrite = false) {
    const path = $("#tex-path").value.trim();
    if (!path) { message("Give the path to save the graph at (a .toml file)", "error"); return false; }
    const r = await api("texture/file", { method: "PUT", json: { path, text: editor.text, overwrite } });
    if (!r.ok) {
      if (r.status === 409 && !overwrite && r.data.error === "workspace"
          && window.confirm(`${path} (or its .png) exists. Replace it?`)) return save(true);
      if (r.data.line) showError(r.data);
      else message(r.data.message, "error");
      return false;
    }
    message(`Saved ${r.data.path} and ${r.data.image}`);
    await listFiles();
    return true;
  }
  tex.save = save;

  async function open() {
    if (tex.opened) { if (!tex.last && !tex.error) await render(); return; }
    tex.opened = true;
    const r = await api("texture/presets");
    if (!r.ok) { message(r.data.message, "error"); return; }
    $("#tex-preset").innerHTML = r.data.presets.map((p) =>
      `<option value="${esc(p.name)}" title="${esc(p.description)}">${esc(p.name)} (${esc(p.kind)})</option>`).join("");
    $("#tex-preset").value = DEFAULT_PRESET;
    await listFiles();
    await pickPreset($("#tex-preset").value);
  }
  tex.open = open;

  $("#tex-preset").onchange = () => pickPreset($("#tex-preset").value);
  $("#tex-files").onchange = () => { if ($("#tex-files").value) openFile($("#tex-files").value); };
  $("#tex-save").onclick = () => save();
  $("#tex-render").onclick = () => render();
}
