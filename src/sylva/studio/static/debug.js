// The debugger dock: breakpoints (a rule fires, a module appears, a condition holds), the
// modules that matched, stepping on from there, and the per-rule profile.
import { checkNumber, markBad, markOk } from "./checks.js";

const $ = (sel) => document.querySelector(sel);

export function initDebugger(ctx) {
  const { api, app, message, esc } = ctx;
  const breakpoints = [];
  app.breakpoints = breakpoints;

  function listRules(s) {
    const sel = $("#bp-rule");
    const keep = sel.value;
    sel.innerHTML = (s.rule_list || []).map((r) =>
      `<option value="${r.index}">${r.index}: ${esc(r.text)}${r.line != null ? ` (line ${r.line})` : ""}</option>`).join("");
    if (keep !== "" && sel.querySelector(`option[value="${keep}"]`)) sel.value = keep;
  }
  ctx.onState.push(listRules);

  function render() {
    const box = $("#bp-list");
    if (!breakpoints.length) { box.innerHTML = '<li class="muted">No breakpoints.</li>'; return; }
    box.innerHTML = breakpoints.map((b, i) => {
      const what = b.kind === "rule" ? `rule ${esc($("#bp-rule").querySelector(`option[value="${b.rule}"]`)?.textContent || b.rule)} fires`
        : b.kind === "module" ? `module ${esc(b.symbol)} appears` : `${esc(b.text)} holds`;
      return `<li data-i="${i}">Stop when ${what} <button class="bp-del" title="Remove">×</button></li>`;
    }).join("");
    for (const btn of box.querySelectorAll(".bp-del")) {
      btn.onclick = () => { breakpoints.splice(Number(btn.parentElement.dataset.i), 1); render(); };
    }
  }

  $("#bp-add").onclick = () => {
    const kind = $("#bp-kind").value;
    if (kind === "rule") {
      const v = $("#bp-rule").value;
      if (v === "") { markBad($("#bp-rule"), "the program has no rules: derive it first"); return; }
      markOk($("#bp-rule"));
      breakpoints.push({ kind, rule: Number(v) });
    } else {
      const el = $("#bp-text");
      const t = el.value.trim();
      if (!t) { markBad(el, kind === "module" ? "a module name, such as F" : "a module and a condition, such as A(x) : x > 3"); return; }
      markOk(el);
      breakpoints.push(kind === "module" ? { kind, symbol: t } : { kind, text: t });
    }
    render();
  };
  $("#bp-kind").onchange = () => {
    const k = $("#bp-kind").value;
    $("#bp-rule").hidden = k !== "rule";
    $("#bp-text").hidden = k === "rule";
    $("#bp-text").placeholder = k === "module" ? "F" : "A(x) : x > 3";
  };
  $("#bp-kind").onchange();

  // Run on to the next breakpoint (at most the step count of the simulation dock).
  async function runToBreak() {
    if (app.busy) return;
    const stepsEl = $("#steps");
    const n = checkNumber(stepsEl);
    if (n === undefined) return;
    if (!app.state && !(await ctx.resetSimulation({ keepOverrides: true }))) return;
    const profile = $("#bp-profile").checked;
    ctx.setBusy(true, n);
    try {
      const r = await api("debug", { method: "POST", json: { n: Math.max(1, n), breakpoints, profile } });
      if (!r.ok) {
        if (r.data && r.data.error === "bad_request" && /breakpoint/.test(r.data.message)) markBad($("#bp-text"), r.data.message);
        ctx.showError(r.data);
        if (r.data && r.data.state) await ctx.refresh();
        return;
      }
      ctx.clearError();
      ctx.showState(r.data);
      showHit(r.data.hit, r.data);
      if (profile) await showProfile();
      await ctx.refresh();
    } finally { ctx.setBusy(false); }
  }

  function showHit(hit, s) {
    app.hit = hit;
    const box = $("#bp-hit");
    if (!hit) {
      box.innerHTML = `<p class="muted">No breakpoint held in ${s.done} steps (now at step ${s.step}).</p>`;
      message(`No breakpoint held; step ${s.step}`);
      return;
    }
    const what = hit.kind === "rule" ? `rule ${hit.rule} fired` : hit.kind === "module" ? `module ${esc(hit.symbol)} appeared` : `${esc(hit.text)} held`;
    box.innerHTML = `<p class="hit">Stopped at step ${hit.step}: ${what} — ${hit.count.toLocaleString("en")} modules matched</p>
      <div class="matched">${hit.matched.map((i) => `<a href="#" data-i="${i}">${i}</a>`).join(" ")}${hit.count > hit.matched.length ? " …" : ""}</div>`;
    for (const a of box.querySelectorAll("a[data-i]")) {
      a.onclick = (e) => { e.preventDefault(); ctx.traceModule(Number(a.dataset.i)); };
    }
    message(`Breakpoint: stopped at step ${hit.step} (${what})`);
  }

  async function showProfile() {
    const r = await api("profile");
    if (!r.ok) return;
    const rules = r.data.rules;
    const rows = [];
    for (const st of r.data.steps.slice(-20)) {
      for (const x of st.rules) {
        rows.push(`<tr><td>${st.step}</td><td>${esc(rules[x.rule]?.text || x.rule)}</td><td>${x.instances.toLocaleString("en")}</td><td>${x.written.toLocaleString("en")}</td><td>${x.ms.toFixed(2)}</td></tr>`);
      }
    }
    $("#profile tbody").innerHTML = rows.join("") || '<tr><td colspan="5" class="muted">No steps profiled yet.</td></tr>';
  }
  $("#bp-run").onclick = runToBreak;
  $("#profile-clear").onclick = async () => { await api("profile", { method: "DELETE" }); await showProfile(); };
  app.runToBreak = runToBreak;
  render();
}
