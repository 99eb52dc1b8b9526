// Bad input refused in place: a field with a value outside its range turns red and says the
// allowed range beside it; the action that would use it does not run.  The server checks
// again (a 400 names the field), never a 500.

// The allowed range of a number field, from its min/max/step attributes (or data-open-min:
// the minimum itself is out).
export function rangeText(el) {
  const lo = el.getAttribute("min"), hi = el.getAttribute("max");
  const open = el.dataset.openMin === "1";
  const whole = el.getAttribute("step") === "1" || el.dataset.integer === "1";
  let t;
  if (lo != null && hi != null) t = `${open ? "(" : "["}${lo}, ${hi}]`;
  else if (lo != null) t = open ? `> ${lo}` : `≥ ${lo}`;
  else if (hi != null) t = `≤ ${hi}`;
  else t = "a number";
  return (whole ? "a whole number " : "") + (lo != null || hi != null ? "in " : "") + t;
}

// The number in a field, or null (and the field marked) when it is not allowed.
export function checkNumber(el, { optional = false } = {}) {
  const text = el.value.trim();
  if (optional && text === "") { markOk(el); return null; }
  const v = Number(text);
  const lo = el.getAttribute("min"), hi = el.getAttribute("max");
  const whole = el.getAttribute("step") === "1" || el.dataset.integer === "1";
  let ok = text !== "" && Number.isFinite(v);
  if (ok && whole && !Number.isInteger(v)) ok = false;
  if (ok && lo != null && (el.dataset.openMin === "1" ? v <= Number(lo) : v < Number(lo))) ok = false;
  if (ok && hi != null && v > Number(hi)) ok = false;
  if (!ok) { markBad(el, `expected ${rangeText(el)}`); return undefined; }
  markOk(el);
  return v;
}

function hint(el) {
  let h = el.nextElementSibling;
  if (!h || !h.classList.contains("field-error")) {
    h = document.createElement("span");
    h.className = "field-error";
    el.insertAdjacentElement("afterend", h);
  }
  return h;
}

export function markBad(el, text) {
  el.classList.add("invalid");
  el.setAttribute("aria-invalid", "true");
  el.title = text;
  const h = hint(el);
  h.textContent = text;
  h.hidden = false;
}

export function markOk(el) {
  if (!el.classList.contains("invalid")) return;
  el.classList.remove("invalid");
  el.removeAttribute("aria-invalid");
  el.title = "";
  const h = el.nextElementSibling;
  if (h && h.classList.contains("field-error")) h.hidden = true;
}

// Check a number field as it is typed.
export function watch(el, opts) {
  el.addEventListener("input", () => checkNumber(el, opts));
}
