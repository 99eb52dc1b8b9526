// The workloads of benchmarks/derive.py, run with lindenmayer (npm) for the ratio.
// Prints one JSON object: {name: {seconds: median, length: final length}}.
"use strict";
const LSystem = require("lindenmayer");

function median(xs) {
  const s = xs.slice().sort((a, b) => a - b);
  return s[Math.floor(s.length / 2)];
}

function time(fn, repeat) {
  const ts = [];
  let out;
  for (let i = 0; i < repeat; i++) {
    const t = process.hrtime.bigint();
    out = fn();
    ts.push(Number(process.hrtime.bigint() - t) / 1e9);
  }
  return { seconds: median(ts), length: out };
}

const which = new Set(process.argv.slice(2));
const res = {};
const want = (n) => which.size === 0 || which.has(n);

if (want("koch")) {
  res.koch = time(() => {
    const ls = new LSystem({ axiom: "F++F++F", productions: { F: "F-F++F-F" } });
    ls.iterate(10);
    return ls.getString().length;
  }, 3);
}
if (want("plant")) {
  res.plant = time(() => {
    const ls = new LSystem({ axiom: "X", productions: { X: "F[+X]F[-X]+X", F: "FF" } });
    ls.iterate(11);
    return ls.getString().length;
  }, 3);
}
if (want("stochastic")) {
  res.stochastic = time(() => {
    const ls = new LSystem({
      axiom: "F",
      productions: {
        F: { successors: [
          { weight: 33, successor: "F[+F]F[-F]F" },
          { weight: 33, successor: "F[+F]F" },
          { weight: 34, successor: "F[-F]F" },
        ] },
      },
    });
    ls.iterate(10);
    return ls.getString().length;
  }, 3);
}
if (want("signal")) {
  const axiom = "b" + "a".repeat(99999);
  res.signal = time(() => {
    const ls = new LSystem({ axiom, productions: { "b<a": "b", b: "a" } });
    ls.iterate(5);
    return ls.getString().length * 5;
  }, 3);
}
if (want("bracketed")) {
  const axiom = require("fs").readFileSync(process.env.SYLVA_BRACKETED_AXIOM, "utf8").trim();
  res.bracketed = time(() => {
    const ls = new LSystem({
      axiom,
      productions: { "S<F": "S", S: "F" },
      branchSymbols: "[]",
      ignoredSymbols: "+-",
    });
    ls.iterate(1);
    return ls.getString().length;
  }, 1);
}
if (want("parametric")) {
  const R = 1.456;
  res.parametric = time(() => {
    const ls = new LSystem({
      axiom: [{ symbol: "A", s: 1 }],
      productions: {
        A: ({ part }) => [
          { symbol: "F", s: part.s }, { symbol: "[" }, { symbol: "+" },
          { symbol: "A", s: part.s / R }, { symbol: "]" }, { symbol: "[" }, { symbol: "-" },
          { symbol: "A", s: part.s / R }, { symbol: "]" },
        ],
      },
    });
    ls.iterate(18);
    return ls.getRaw().length;
  }, 1);
}
process.stdout.write(JSON.stringify(res) + "\n");
