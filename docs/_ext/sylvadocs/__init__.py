"""Sphinx directives that generate sylva's reference pages from sylva itself.

``.. sylva-grammar::``
    The ``.lsys`` grammar as EBNF, read from the shipped ``lsys.lark`` at build time.
``.. sylva-turtle-table:: TABLE``
    The turtle command table ``TABLE`` (``lsys``, ``abop``, ``classic`` or ``engine``) of
    :mod:`sylva.turtle.tables`, one row per command with a picture rendered by sylva.
``.. sylva-gallery::``
    Every built-in example with its picture, the command that makes it and its text.

Pictures are rendered once, when the build starts, into ``_build/.sylva-cache`` (see
:mod:`.pictures`); a later build reuses them.
"""

from __future__ import annotations

import importlib
import time
import types
from pathlib import Path

from docutils import nodes
from docutils.parsers.rst import Directive
from docutils.statemachine import StringList
from sphinx.util import logging
from sphinx.util.nodes import nested_parse_with_titles

from . import catalog, pictures

_log = logging.getLogger(__name__)
CACHE = Path("_build") / ".sylva-cache"


def _jobs() -> list[pictures.Job]:
    jobs = [pictures.Job("example", e.name, pictures.GALLERY_SIZE)
            for e in catalog.gallery_entries()]
    jobs += [pictures.Job("texture", n, pictures.TEXTURE_SIZE)
             for n in catalog.gallery_textures()]
    jobs.append(SHEET)
    for table in ("lsys", "abop", "classic", "engine"):
        jobs += [pictures.Job("turtle", r.program, pictures.TURTLE_SIZE)
                 for r in catalog.turtle_rows(table)]
    return jobs


#: Every tree species at three ages, on one scale (``sylva tree --sheet``).
SHEET = pictures.Job("trees", "species", (0, 0))


def _render(app) -> None:
    t = time.perf_counter()
    made = pictures.render_missing(_jobs(), Path(app.srcdir) / CACHE)
    if made:
        _log.info(f"sylva: rendered {len(made)} pictures in {time.perf_counter() - t:.1f} s")


def _image(job: pictures.Job) -> str:
    return f"/{CACHE.as_posix()}/{job.filename()}"


class _Generated(Directive):
    """A directive whose output is reStructuredText made by :meth:`lines`."""

    def lines(self) -> list[str]:
        raise NotImplementedError

    def depends_on(self) -> list[Path]:
        """Files whose change makes this page be built again."""
        here = Path(__file__).resolve().parent
        return [here / "__init__.py", here / "catalog.py", here / "pictures.py"]

    def run(self):
        env = self.state.document.settings.env
        for path in self.depends_on():
            env.note_dependency(str(path))
        node = nodes.section() if self.has_titles else nodes.container()
        source = self.state.document.current_source
        content = StringList([line for line in self.lines()], source=source)
        if self.has_titles:
            nested_parse_with_titles(self.state, content, node)
        else:
            self.state.nested_parse(content, self.content_offset, node)
        return node.children

    has_titles = False


def _indent(text: str, n: int = 3) -> list[str]:
    return [(" " * n + line) if line.strip() else "" for line in text.splitlines()]


class GrammarDirective(_Generated):
    def depends_on(self):
        return [*super().depends_on(), catalog.grammar_path()]

    def lines(self):
        rules, terminals = catalog.grammar_ebnf()
        return ([".. code-block:: ebnf", "   :caption: Rules (from lsys.lark)", ""]
                + _indent(rules) + ["", ".. code-block:: text",
                                    "   :caption: Terminals: regular expressions", ""]
                + _indent(terminals) + [""])


def _literal(text: str) -> str:
    """``text`` as inline literal (escaping a backslash or a backquote)."""
    if "`" in text or "\\" in text:
        return ":code:`" + text.replace("\\", "\\\\").replace("`", "\\`") + "`"
    return f"``{text}``"


class TurtleTableDirective(_Generated):
    required_arguments = 1

    def depends_on(self):
        from sylva.turtle import tables

        return [*super().depends_on(), Path(tables.__file__)]

    def lines(self):
        table = self.arguments[0]
        out = [".. list-table::", "   :header-rows: 1", "   :widths: 8 18 44 30",
               "   :class: sylva-turtle", "", "   * - symbol", "     - parameters",
               "     - meaning", "     - shown by"]
        for row in catalog.turtle_rows(table):
            job = pictures.Job("turtle", row.program, pictures.TURTLE_SIZE)
            axiom = row.program.rsplit("axiom = ", 1)[1].strip()
            syms = (_literal(catalog.symbols_text(row.symbols)) if len(row.symbols) > 3
                    else " ".join(_literal(s) for s in row.symbols))
            out += [f"   * - {syms}", f"     - {row.command.params or '—'}",
                    f"     - {row.command.meaning}",
                    f"     - .. image:: {_image(job)}", "          :width: 96",
                    f"          :alt: {row.opcode}", "",
                    f"       {_literal(axiom)}"]
        return out + [""]


class GalleryDirective(_Generated):
    has_titles = True

    def depends_on(self):
        import sylva.tree

        species = sorted((Path(sylva.tree.__file__).parent / "species").glob("*"))
        return [*super().depends_on(), *(e.path for e in catalog.gallery_entries()), *species]

    def lines(self):
        entries = catalog.gallery_entries()
        out = [".. container:: sylva-grid", ""]
        for e in entries:
            job = pictures.Job("example", e.name, pictures.GALLERY_SIZE)
            out += [f"   .. figure:: {_image(job)}", f"      :target: #{e.name}",
                    f"      :alt: {e.name}", "", f"      {e.name}", ""]
        for e in entries:
            job = pictures.Job("example", e.name, pictures.GALLERY_SIZE)
            text = e.path.read_text(encoding="utf-8")
            out += [f".. _{e.name}:", "", e.name, "-" * len(e.name), "",
                    e.title.replace("*", "\\*") + "", "",
                    f".. image:: {_image(job)}", "   :width: 360", f"   :alt: {e.name}", "",
                    ".. code-block:: sh", "", f"   {e.command}", "",
                    f".. code-block:: {e.language}", f"   :caption: {e.path.name}", ""]
            out += _indent(text) + [""]
        out += ["Tree species", "------------", "",
                "Every shipped tree species (:doc:`tutorials/trees`) at three ages, on one "
                "scale (the red bar is 5 m), as ``sylva tree --sheet -o sheet.png`` draws "
                "them; ``sylva tree --list`` names each species and the source of its "
                "parameters.", "",
                f".. image:: {_image(SHEET)}", "   :alt: the tree species contact sheet", ""]
        out += ["Textures", "--------", "",
                "Some of the texture presets (:doc:`tutorials/textures`), as ``sylva gallery`` "
                "renders them; each is ``sylva texture NAME -o NAME.png``.", "",
                ".. container:: sylva-grid", ""]
        for name in catalog.gallery_textures():
            job = pictures.Job("texture", name, pictures.TEXTURE_SIZE)
            out += [f"   .. figure:: {_image(job)}", f"      :alt: {name}", "",
                    f"      ``{name}``", ""]
        return out


class CliDirective(_Generated):
    """Every sub-command's ``--help``, as argparse prints it."""

    has_titles = True

    def depends_on(self):
        import sylva.cli

        return [*super().depends_on(), *Path(sylva.cli.__file__).parent.glob("*.py")]

    def lines(self):
        out = []
        for name, text in catalog.cli_commands().items():
            title = f"sylva {name}"
            out += [f".. _cli-{name}:", "", title, "-" * len(title), "",
                    ".. code-block:: text", ""] + _indent(text) + [""]
        return out


class ApiDirective(_Generated):
    """The functions and classes of a module's ``__all__``, from their docstrings."""

    required_arguments = 1
    has_titles = True

    def lines(self):
        module = self.arguments[0]
        functions, classes = catalog.api_names(module)
        out = [f".. automodule:: {module}", "   :no-members:", "", f".. currentmodule:: {module}",
               "", ".. rubric:: Contents", "", ".. autosummary::", ""]
        out += [f"   {n}" for n in functions + classes] + [""]
        mod = importlib.import_module(module)
        for n in functions:
            target = f"{module}.{n}"
            if isinstance(getattr(mod, n), types.ModuleType):
                # sylva.tree and sylva.world are callable subpackages with pages of their
                # own: here they are documented as the functions the call runs
                target = f"sylva.grown.{n}"
            out += [f".. autofunction:: {target}", ""]
        for n in classes:
            out += [f".. autoclass:: {module}.{n}", "   :members:", ""]
        return out


class ExampleImageDirective(_Generated):
    """The gallery picture of one built-in example (``.. sylva-example:: NAME``)."""

    required_arguments = 1

    def lines(self):
        from sylva.data import find

        name = find(self.arguments[0]).name
        job = pictures.Job("example", name, pictures.GALLERY_SIZE)
        return [f".. figure:: {_image(job)}", "   :width: 300", f"   :alt: {name}", "",
                f"   ``{name}`` (:ref:`in the gallery <{name}>`)", ""]


def setup(app):
    app.add_directive("sylva-grammar", GrammarDirective)
    app.add_directive("sylva-turtle-table", TurtleTableDirective)
    app.add_directive("sylva-gallery", GalleryDirective)
    app.add_directive("sylva-example", ExampleImageDirective)
    app.add_directive("sylva-cli", CliDirective)
    app.add_directive("sylva-api", ApiDirective)
    app.connect("builder-inited", _render)
    return {"version": pictures.VERSION, "parallel_read_safe": True,
            "parallel_write_safe": True}
