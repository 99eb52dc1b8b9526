// The definition editor: CodeMirror 6 with highlighting of the three L-system languages and
// error markers (a gutter marker, an underlined range and a message) at the line and column
// the server's parser reports.
import {
  EditorState, EditorView, keymap, lineNumbers, highlightActiveLine, highlightActiveLineGutter,
  drawSelection, defaultKeymap, history, historyKeymap, indentWithTab, StreamLanguage,
  syntaxHighlighting, HighlightStyle, bracketMatching, lintGutter, setDiagnostics,
  searchKeymap, highlightSelectionMatches, tags, StateEffect, StateField, Decoration,
} from "./vendor/codemirror.js";

// a slider's value as the text writes it: at most 6 significant digits, no trailing zeros
export function formatNumber(v) {
  if (!Number.isFinite(v)) return String(v);
  return String(Number(v.toPrecision(6)));
}

const SPECIAL = new Set([
  "axiom", "ignore", "consider", "detail", "bg", "len", "thick", "rot", "color", "len_delta",
  "thick_delta", "rot_delta", "color_delta", "steps", "seed", "iteration", "iterations",
  "angle", "reduction", "turtle", "radius", "thickness", "rule", "rules", "define",
]);
const FUNCS = new Set(["sum", "sqrt", "sin", "cos", "tan", "abs", "pow", "True", "False"]);

// A stream tokenizer good for all three dialects: comments, arrows, numbers, quoted long
// names, assignment targets, turtle symbols and module names.
const lsysLanguage = StreamLanguage.define({
  name: "lsys",
  startState: () => ({ inParams: 0, lineStart: true }),
  token(stream, state) {
    if (stream.sol()) { state.lineStart = true; state.inParams = 0; }
    if (stream.eatSpace()) return null;
    const start = state.lineStart;
    state.lineStart = false;
    if (stream.match(/^(#|\/\/)/)) { stream.skipToEnd(); return "comment"; }
    if (start && stream.match(/^;/) && stream.peek() === " ") { stream.skipToEnd(); return "comment"; }
    if (stream.match(/^->>?/) || stream.match(/^-->/) || stream.match(/^=>/)) return "keyword";
    if (stream.match(/^"[^"\n]*"?/)) return "string";
    if (state.inParams > 0) {
      if (stream.match(/^\d+\.?\d*(e[-+]?\d+)?|^\.\d+/i)) return "number";
      if (stream.match(/^[A-Za-z_][A-Za-z0-9_]*/)) {
        return FUNCS.has(stream.current()) ? "keyword" : "variableName";
      }
      if (stream.eat("(")) { state.inParams++; return "bracket"; }
      if (stream.eat(")")) { state.inParams--; return "bracket"; }
      stream.next();
      return "operator";
    }
    if (start) {
      const m = stream.match(/^([A-Za-z_][A-Za-z0-9_]*)(?=\s*[=:](?![=>]))/);
      if (m) return SPECIAL.has(m[1]) ? "keyword" : "definition";
      if (stream.match(/^-?\d+\.?\d*/)) return "number";
    }
    if (stream.match(/^[=:]/)) { state.inParams = 1; return "operator"; }
    if (stream.match(/^\d+\.?\d*(e[-+]?\d+)?/i) && stream.current().length > 1) return "number";
    if (stream.eat("(")) { state.inParams = 1; return "bracket"; }
    if (stream.match(/^[<>]/)) return "operator";
    const ch = stream.next();
    if ("[]".includes(ch)) return "bracket";
    if ("+-^&\\/|$!~;_{}.%'".includes(ch)) return "operator";
    if (/[A-Z]/.test(ch)) return "typeName";
    return "atom";
  },
  languageData: { commentTokens: { line: "#" } },
});

// TOML, for the texture graphs of Texture mode: comments, table headers, keys, strings,
// numbers and booleans
export const tomlLanguage = StreamLanguage.define({
  name: "toml",
  startState: () => ({ multi: null }),
  token(stream, state) {
    if (state.multi) {
      if (stream.skipTo(state.multi)) { stream.match(state.multi); state.multi = null; }
      else stream.skipToEnd();
      return "string";
    }
    if (stream.eatSpace()) return null;
    if (stream.match("#")) { stream.skipToEnd(); return "comment"; }
    if (stream.sol() && stream.match(/^\[\[?[^\]]*\]\]?/)) return "typeName";
    const q = stream.match(/^('''|""")/);
    if (q) { state.multi = q[1]; return "string"; }
    if (stream.match(/^"(?:[^"\\]|\\.)*"?/) || stream.match(/^'[^']*'?/)) return "string";
    if (stream.match(/^(true|false)\b/)) return "keyword";
    if (stream.match(/^[-+]?(\d[\d_]*\.?[\d_]*(e[-+]?\d+)?|inf|nan)/i)) return "number";
    if (stream.match(/^[A-Za-z0-9_-]+(?=\s*=)/)) return "definition";
    stream.next();
    return "operator";
  },
  languageData: { commentTokens: { line: "#" } },
});

const highlight = HighlightStyle.define([
  { tag: tags.comment, color: "#8a8a8a", fontStyle: "italic" },
  { tag: tags.keyword, color: "#7a2d91", fontWeight: "bold" },
  { tag: tags.string, color: "#a05a00" },
  { tag: tags.number, color: "#1c6fb5" },
  { tag: tags.definition(tags.variableName), color: "#00707a", fontWeight: "bold" },
  { tag: tags.variableName, color: "#00707a" },
  { tag: tags.operator, color: "#b3261e" },
  { tag: tags.bracket, color: "#555" },
  { tag: tags.typeName, color: "#2f6f3e", fontWeight: "bold" },
  { tag: tags.atom, color: "#3a5a2a" },
]);

// a whole-line background on the error line, in addition to the lint range
const setErrorLine = StateEffect.define();
const errorLine = StateField.define({
  create: () => Decoration.none,
  update(deco, tr) {
    deco = deco.map(tr.changes);
    for (const e of tr.effects) {
      if (e.is(setErrorLine)) {
        deco = e.value == null ? Decoration.none
          : Decoration.set([Decoration.line({ class: "cm-error-line" }).range(e.value)]);
      }
    }
    return deco;
  },
  provide: (f) => EditorView.decorations.from(f),
});

export class Editor {
  constructor(parent, { onChange, onCursor, onRun, onSave, language = lsysLanguage } = {}) {
    this.onChange = onChange || (() => {});
    this.onCursor = onCursor || (() => {});
    const runKeys = keymap.of([
      { key: "Mod-Enter", run: () => { onRun && onRun(); return true; } },
      { key: "Mod-s", run: () => { onSave && onSave(); return true; }, preventDefault: true },
    ]);
    this.view = new EditorView({
      parent,
      state: EditorState.create({
        doc: "",
        extensions: [
          lineNumbers(), highlightActiveLineGutter(), history(), drawSelection(),
          bracketMatching(), highlightActiveLine(), highlightSelectionMatches(),
          language, syntaxHighlighting(highlight), lintGutter(), errorLine, runKeys,
          keymap.of([...defaultKeymap, ...historyKeymap, ...searchKeymap, indentWithTab]),
          EditorView.updateListener.of((u) => {
            if (u.docChanged) {
              this.clearError();
              this.onChange(this.text);
            }
            if (u.selectionSet || u.docChanged) this._cursor();
          }),
        ],
      }),
    });
  }

  get text() { return this.view.state.doc.toString(); }

  setText(text) {
    this.view.dispatch({ changes: { from: 0, to: this.view.state.doc.length, insert: text } });
    this.clearError();
  }

  // Set the number a global is assigned in the text (``name = 2.5`` of .lsys and the
  // classic format, cpfg's ``#define name 2.5``), as one undoable edit; false when the text
  // assigns it no plain number.
  setNumber(name, value) {
    const doc = this.view.state.doc.toString();
    const esc = name.replace(/[.*+?^${}()|[\]\\]/g, "\\$&");
    const res = [
      new RegExp(`^([ \\t]*${esc}[ \\t]*[=:][ \\t]*)(-?(?:\\d+\\.?\\d*|\\.\\d+)(?:e[-+]?\\d+)?)`, "mi"),
      new RegExp(`^([ \\t]*#define[ \\t]+${esc}[ \\t]+)(-?(?:\\d+\\.?\\d*|\\.\\d+)(?:e[-+]?\\d+)?)`, "mi"),
    ];
    for (const re of res) {
      const m = re.exec(doc);
      if (!m) continue;
      const from = m.index + m[1].length, to = from + m[2].length;
      const text = formatNumber(value);
      if (doc.slice(from, to) !== text) {
        this.view.dispatch({ changes: { from, to, insert: text }, userEvent: "input.slider" });
      }
      return true;
    }
    return false;
  }

  _cursor() {
    const pos = this.view.state.selection.main.head;
    const line = this.view.state.doc.lineAt(pos);
    this.onCursor(line.number, pos - line.from + 1);
  }

  // Mark an error at a 1-based line and column (the server's LSystemSyntaxError).
  showError(line, column, message) {
    const doc = this.view.state.doc;
    const ln = doc.line(Math.max(1, Math.min(line || 1, doc.lines)));
    const col = Math.max(1, column || 1);
    const from = Math.min(ln.from + col - 1, ln.to);
    const to = Math.min(Math.max(from + 1, ln.to), doc.length);
    const diag = [{ from, to: Math.max(to, from), severity: "error", message }];
    this.view.dispatch(setDiagnostics(this.view.state, diag));
    this.view.dispatch({ effects: setErrorLine.of(ln.from) });
    this.error = { line: ln.number, column: col, message };
  }

  clearError() {
    if (!this.error) return;
    this.error = null;
    this.view.dispatch(setDiagnostics(this.view.state, []));
    this.view.dispatch({ effects: setErrorLine.of(null) });
  }

  goTo(line, column = 1) {
    const doc = this.view.state.doc;
    const ln = doc.line(Math.max(1, Math.min(line, doc.lines)));
    const pos = Math.min(ln.from + column - 1, ln.to);
    this.view.dispatch({ selection: { anchor: pos, head: ln.to }, scrollIntoView: true });
    this.view.focus();
  }
}
