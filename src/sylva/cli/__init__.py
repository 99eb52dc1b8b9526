"""The ``sylva`` command line.

Each sub-command lives in its own module of this package and exposes
``register(subparsers)``, which adds its parser and sets ``func`` to a callable taking the
parsed arguments and returning an exit status.  Modules are discovered, so adding a command
touches no other file.  A :class:`~sylva.errors.SylvaError` is printed without a traceback
and exits with status 2.
"""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import sys

from .._jit import announce
from ..errors import SylvaError

__all__ = ["build_parser", "main"]


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="sylva",
        description="Grow plants, their textures and the worlds they stand in.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        mod = importlib.import_module(f"{__name__}.{info.name}")
        register = getattr(mod, "register", None)
        if register is not None:
            register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    progress = announce()  # a first run compiles kernels: say so on stderr, with progress
    try:
        return int(args.func(args) or 0)
    except SylvaError as exc:
        print(f"sylva: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("sylva: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    finally:
        progress.finish()
