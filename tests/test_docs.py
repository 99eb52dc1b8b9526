"""The documentation covers sylva, and every example in it runs.

The site itself is built by ``make docs`` (Sphinx, in ``.ci/run``); these tests need no
Sphinx.  They fail when something new has no documentation: a dialect without a page, a
turtle command without a meaning or a picture, an example without a gallery entry, a
module whose docstring examples do not run, a page whose Python examples print something
else than the page says.
"""

from __future__ import annotations

import doctest
import importlib
import importlib.util
import pkgutil
import re
import sys
from pathlib import Path

import pytest

import sylva
from sylva.data import examples, find
from sylva.lsystem.dialects import DIALECTS
from sylva.turtle.tables import OPCODE_NAMES, TABLES

DOCS = Path(__file__).resolve().parents[1] / "docs"


def _catalog():
    """``docs/_ext/sylvadocs/catalog.py``, loaded by path: the Sphinx extension around it
    needs Sphinx, the catalog does not."""
    spec = importlib.util.spec_from_file_location(
        "sylvadocs_catalog", DOCS / "_ext" / "sylvadocs" / "catalog.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module


catalog = _catalog()

OPTIONS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def _directives(name: str) -> dict[str, list[str]]:
    """Every page that uses the directive ``name``, with its arguments."""
    found: dict[str, list[str]] = {}
    for page in DOCS.rglob("*.rst"):
        if "_build" in page.parts:
            continue
        for m in re.finditer(rf"^\.\. {re.escape(name)}::[ \t]*(\S*)", page.read_text("utf-8"),
                             re.MULTILINE):
            found.setdefault(str(page.relative_to(DOCS)), []).append(m.group(1))
    return found


def _in_toctree(page: str) -> bool:
    """Whether ``page`` (relative to docs/) is listed by a toctree of the site."""
    doc = page.removesuffix(".rst")
    for index in DOCS.rglob("*.rst"):
        text = index.read_text("utf-8")
        rel = index.parent.relative_to(DOCS)
        for m in re.finditer(r"^\.\. toctree::\n((?:[ \t]+.*\n|\n)*)", text, re.MULTILINE):
            for line in m.group(1).splitlines():
                entry = line.strip()
                if entry and not entry.startswith(":") and str(rel / entry) in (doc, f"./{doc}"):
                    return True
    return False


# ------------------------------------------------------------------------------ languages


def test_every_dialect_has_a_page_with_its_turtle_table():
    assert set(catalog.DIALECT_PAGES) == set(DIALECTS)
    tables = _directives("sylva-turtle-table")
    for dialect, page in catalog.DIALECT_PAGES.items():
        assert (DOCS / page).is_file(), page
        assert _in_toctree(page), f"{page} is in no toctree"
        assert catalog.DIALECT_TURTLE[dialect] in tables.get(page, []), (dialect, page)


def test_every_turtle_table_is_shown():
    shown = {arg for args in _directives("sylva-turtle-table").values() for arg in args}
    assert shown == set(TABLES)


@pytest.mark.parametrize("table", sorted(TABLES))
def test_every_turtle_command_has_a_meaning_and_a_picture_word(table):
    rows = catalog.turtle_rows(table)
    assert sorted(s for r in rows for s in r.symbols) == sorted(TABLES[table])
    for row in rows:
        assert row.opcode in OPCODE_NAMES.values()
        assert row.command.meaning
        program = sylva.loads(row.program)  # the picture's word is valid .lsys
        assert program.turtle == table
        shown = {m.symbol for m in program.axiom}
        assert shown & set(row.symbols), (table, row.symbols, row.program)


def test_the_grammar_page_shows_every_rule_of_lsys_lark():
    text = catalog.grammar_path().read_text("utf-8")
    defined = set(re.findall(r"^[?_!]*([A-Za-z]\w*)\s*:", text, re.MULTILINE))
    rules, terminals = catalog.grammar_ebnf(text)
    shown = set(re.findall(r"^(\w+)\s+=", rules + "\n" + terminals, re.MULTILINE))
    # terminals that are one fixed string appear inside the rules instead
    fixed = {n for n in defined if re.search(rf'^{n}\s*:\s*"[^"]*"\s*$', text, re.MULTILINE)}
    assert shown == defined - fixed
    assert '"->>"' in rules and "{ sitem }" in rules
    assert _directives("sylva-grammar") == {"languages/lsys.rst": [""]}


# -------------------------------------------------------------------------------- gallery


def test_every_example_has_a_gallery_entry_with_a_working_name():
    entries = catalog.gallery_entries()
    assert [e.name for e in entries] == [e.name for e in examples()]
    for e in entries:
        assert find(e.name).path == e.path
        assert e.command == f"sylva render {e.name} -o {e.name}.png"
    assert "gallery.rst" in _directives("sylva-gallery")
    assert _in_toctree("gallery.rst")
    from sylva.texture import PRESETS

    textures = catalog.gallery_textures()
    assert textures and set(textures) <= set(PRESETS)


def test_every_api_module_has_a_page():
    pages = {p.stem for p in (DOCS / "api").glob("*.rst")}
    for module in catalog.API_MODULES:
        slug = module.replace(".", "-")
        assert slug in pages
        assert f".. sylva-api:: {module}\n" in (DOCS / "api" / f"{slug}.rst").read_text("utf-8")
        functions, classes = catalog.api_names(module)
        assert functions or classes, module


def test_every_command_is_on_the_cli_page():
    commands = catalog.cli_commands()
    assert {"derive", "render", "export", "tree", "texture", "world", "studio"} <= set(commands)
    assert _directives("sylva-cli") == {"cli.rst": [""]}


# ------------------------------------------------------------------------------- doctests


def _public_modules() -> list[str]:
    names = ["sylva"]
    for info in pkgutil.walk_packages(sylva.__path__, "sylva."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.append(info.name)
    return sorted(names)


@pytest.mark.parametrize("name", _public_modules())
def test_docstring_examples_of_every_public_module_run(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=OPTIONS, report=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples fail in {name}"


def _pages_with_examples() -> list[str]:
    return sorted(str(p.relative_to(DOCS)) for p in DOCS.rglob("*.rst")
                  if "_build" not in p.parts and "\n>>> " in p.read_text("utf-8"))


_CAPTIONED = re.compile(
    r"^\.\. code-block:: \w+\n   :caption: ([\w.\-]+)(?:[, ].*)?\n\n((?:   .*\n|\n)+)", re.MULTILINE
)


@pytest.mark.slow
@pytest.mark.parametrize("page", _pages_with_examples())
def test_the_python_examples_of_every_page_run(page, tmp_path, monkeypatch):
    """Run a page's ``>>>`` examples in an empty folder holding the files the page shows
    (each ``code-block`` with a file name as caption), as a reader would have them."""
    text = (DOCS / page).read_text("utf-8")
    for name, body in _CAPTIONED.findall(text):
        lines = [line[3:] for line in body.rstrip("\n").split("\n")]
        (tmp_path / name).write_text("\n".join(lines) + "\n", encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    result = doctest.testfile(str(DOCS / page), module_relative=False, optionflags=OPTIONS,
                              report=False, encoding="utf-8")
    assert result.attempted > 0
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples fail in {page}"
