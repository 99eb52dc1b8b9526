// Builds the Studio's vendor bundles into ../static/vendor/ (run: npm ci && npm run build).
// The bundles are committed, so installing sylva needs no Node; only changing them does.
import { build } from "esbuild";
import { copyFileSync, mkdirSync, readFileSync } from "node:fs";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const here = dirname(fileURLToPath(import.meta.url));
const out = join(here, "..", "static", "vendor");
mkdirSync(join(out, "licenses"), { recursive: true });

const common = { bundle: true, format: "esm", minify: true, target: "es2020", legalComments: "none" };
await build({ ...common, entryPoints: [join(here, "three-entry.js")], outfile: join(out, "three.js") });
await build({ ...common, entryPoints: [join(here, "codemirror-entry.js")], outfile: join(out, "codemirror.js") });

// Every package that ends up in a bundle, with its licence text.
const bundled = [
  "three", "@codemirror/state", "@codemirror/view", "@codemirror/commands",
  "@codemirror/language", "@codemirror/lint", "@codemirror/search", "@codemirror/autocomplete",
  "@lezer/common", "@lezer/highlight", "@lezer/lr", "@marijn/find-cluster-break", "crelt",
  "style-mod", "w3c-keyname",
];
const lines = [];
for (const name of bundled) {
  const dir = join(here, "node_modules", name);
  const pkg = JSON.parse(readFileSync(join(dir, "package.json"), "utf8"));
  const file = ["LICENSE", "LICENSE.md", "LICENSE.txt", "license"].find((f) => {
    try { readFileSync(join(dir, f)); return true; } catch { return false; }
  });
  if (!file) throw new Error(`no licence file in ${name}`);
  const dest = `${name.replace("/", "__")}.LICENSE`;
  copyFileSync(join(dir, file), join(out, "licenses", dest));
  lines.push(`${name} ${pkg.version} ${pkg.license} licenses/${dest}`);
}
const { writeFileSync } = await import("node:fs");
writeFileSync(join(out, "VENDORED.txt"), "# package version licence file\n" + lines.join("\n") + "\n");
console.log(lines.join("\n"));
