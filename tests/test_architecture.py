"""The shape of the package: the public API and the direction of imports (DESIGN.md)."""

import ast
from pathlib import Path

import sylva

SRC = Path(sylva.__file__).parent

# package -> the sylva packages it may import (besides errors, data and itself)
ALLOWED = {
    "lsystem": set(),
    "geometry": set(),
    "texture": set(),
    "turtle": {"lsystem", "geometry"},
    "render": {"geometry", "texture"},
    "tree": {"lsystem", "turtle", "geometry", "texture"},
    "world": {"tree", "turtle", "geometry", "texture", "lsystem", "cluster"},
}
FREE = {"errors", "data", "_version", "_atomic", "_jit"}


def _imports(path: Path, package: str) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    rel_parts = path.relative_to(SRC).parts
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = list(rel_parts[:-1])[: len(rel_parts) - node.level]
                mod = ".".join(base + ([node.module] if node.module else []))
                target = mod.split(".")[0] if mod else ""
                if not target and node.names:
                    target = node.names[0].name
            elif node.module and node.module.startswith("sylva"):
                parts = node.module.split(".")
                target = parts[1] if len(parts) > 1 else ""
            else:
                continue
            found.add(target)
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("sylva."):
                    found.add(a.name.split(".")[1])
    found.discard(package)
    return found


def test_imports_flow_one_way():
    bad = []
    for package, allowed in ALLOWED.items():
        folder = SRC / package
        if not folder.exists():
            continue
        for path in folder.rglob("*.py"):
            for target in _imports(path, package):
                if target in FREE or target in allowed or target == "":
                    continue
                bad.append(f"{path.relative_to(SRC)} imports sylva.{target}")
    assert not bad, "\n".join(bad)


def test_nothing_imports_cli_studio_or_widgets():
    # _shown.py's Shown.show() is the one door to the widgets, imported inside the method
    bad = []
    for path in SRC.rglob("*.py"):
        pkg = path.relative_to(SRC).parts[0]
        if pkg in ("cli", "studio", "widgets", "__main__.py"):
            continue
        hits = _imports(path, pkg) & {"cli", "studio", "widgets"}
        if pkg == "_shown.py":
            hits -= {"widgets"}
        if hits:
            bad.append(f"{path.relative_to(SRC)} imports {hits}")
    assert not bad, "\n".join(bad)


def test_public_api_is_pinned():
    assert sorted(sylva.__all__) == sylva.__all__
    for name in sylva.__all__:
        assert getattr(sylva, name) is not None
    assert set(sylva.__all__) == {
        "Derivation", "GrowthLimitError", "LSystemSemanticError", "LSystemSyntaxError",
        "ModuleString", "Program", "SylvaError", "define", "derive", "dumps", "grow", "iterate",
        "load", "load_all", "loads", "render_word", "tree", "world",
    }
    assert callable(sylva.grow) and callable(sylva.tree) and callable(sylva.world)


def test_import_sylva_stays_light():
    import subprocess
    import sys

    code = ("import sys, sylva; print(sorted(m for m in ('moderngl', 'starlette', "
            "'sylva.render', 'sylva.tree', 'sylva.world', 'sylva.widgets', 'anywidget') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "[]"


def test_user_text_never_reaches_eval_or_exec():
    for path in SRC.rglob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
                assert node.func.id not in ("eval", "exec"), path


def test_modules_stay_small():
    big = [
        (p.relative_to(SRC), n)
        for p in SRC.rglob("*.py")
        if (n := len(p.read_text(encoding="utf-8").splitlines())) > 1200
    ]
    assert not big, big


def test_subpackages_are_not_shadowed_by_names():
    import importlib

    for sub in ("lsystem", "turtle", "geometry", "texture", "render", "tree", "world"):
        mod = importlib.import_module(f"sylva.{sub}")
        assert getattr(sylva, sub, mod) is mod, f"sylva.{sub} is shadowed by a name"
