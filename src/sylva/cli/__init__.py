"""The ``sylva`` command line.

Each sub-command lives in its own module of this package and exposes
``register(subparsers)``, which adds its parser and sets ``func`` to a callable taking the
parsed arguments and returning an exit status.  Modules are discovered, so adding a command
touches no other file.  A :class:`~sylva.errors.SylvaError` is printed without a traceback
and exits with status 2; so is an ``OSError`` (a missing folder, no permission, a full disk),
as one line naming the file and the cause.  Every output is written atomically (see
:mod:`sylva._atomic`), so a failed command leaves the previous file as it was.
"""

from __future__ import annotations

import argparse
import errno
import importlib
import os
import pkgutil
import sys
import warnings

from .._atomic import describe_os_error, is_write_error
from .._jit import announce
from ..errors import SylvaError, SylvaWarning

__all__ = ["build_parser", "main"]

#: Commands whose ``--out`` is a folder they make (the others' outputs are files).
_FOLDER_OUTPUTS = {"gallery", "demo"}


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


def _check_output_folder(args: argparse.Namespace) -> None:
    """Fail before the work, not after it, when the output's folder is missing."""
    path = getattr(args, "output", None)
    if path is None and args.command not in _FOLDER_OUTPUTS:
        path = getattr(args, "out", None)
    if not isinstance(path, str) or not path:
        return
    folder = os.path.dirname(os.path.abspath(path))
    if os.path.isdir(folder):
        return
    up = folder
    while not os.path.exists(up):
        up = os.path.dirname(up)
    code = errno.ENOENT if os.path.isdir(up) else errno.ENOTDIR
    exc = OSError(code, os.strerror(code), path)
    exc.sylva_write = True
    raise exc


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """Input warnings (a view-file line sylva cannot honour) as one line on stderr."""
    print(f"sylva: warning: {message}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    with warnings.catch_warnings():
        warnings.simplefilter("always", SylvaWarning)  # each input line once, on stderr
        warnings.showwarning = _show_warning
        return _main(argv)


def _main(argv: list[str] | None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    progress = announce()  # a first run compiles kernels: say so on stderr, with progress
    try:
        _check_output_folder(args)
        return int(args.func(args) or 0)
    except SylvaError as exc:
        print(f"sylva: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("sylva: interrupted", file=sys.stderr)
        return 130
    except OSError as exc:
        if isinstance(exc, BrokenPipeError) and exc.filename is None:
            return 0  # stdout closed early (sylva derive ... | head); not a failed write
        # a write names its output ("cannot write OUT: the disk is full"); anything else
        # (a file that could not be read) is said without claiming it was a write
        verb = "write" if is_write_error(exc) else "open"
        print(f"sylva: error: {describe_os_error(exc, verb=verb)}", file=sys.stderr)
        return 2
    finally:
        progress.finish()
