"""``sylva studio``: the interactive L-system workbench in the browser."""

from __future__ import annotations

from pathlib import Path

from ..errors import SylvaError

__all__ = ["register"]


def register(sub) -> None:
    p = sub.add_parser(
        "studio",
        help="open the interactive L-system workbench in the browser",
        description="Serve the Studio on 127.0.0.1 and open it in the browser: edit a "
        "definition, step it, view it in 3D, trace rules, save files in the workspace.",
    )
    p.add_argument("file", metavar="FILE", nargs="?", default=None,
                   help="a definition to open (inside the workspace), or a built-in "
                        "example name")
    p.add_argument("--port", type=int, default=8765,
                   help="port on 127.0.0.1 (default 8765; 0 picks a free one)")
    p.add_argument("--workspace", metavar="DIR", default=None,
                   help="the folder files are opened from and saved to (default: FILE's "
                        "folder, else the current folder)")
    p.add_argument("--no-browser", action="store_true", help="do not open a browser")
    p.add_argument("--max-modules", type=int, default=None,
                   help="module cap of a derivation (default 2,000,000)")
    p.add_argument("--time-cap", type=float, default=None,
                   help="seconds one request may derive or mesh (default 10)")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..studio import Limits, serve

    if not 0 <= args.port <= 65535:
        raise SylvaError(f"--port must be 0 to 65535, not {args.port}")
    start = None
    workspace = Path(args.workspace) if args.workspace else None
    if args.file:
        f = Path(args.file)
        if f.is_file():
            workspace = workspace or f.resolve().parent
            try:
                start = "file:" + f.resolve().relative_to(workspace.resolve()).as_posix()
            except ValueError:
                raise SylvaError(f"{args.file} is not inside the workspace {workspace}; "
                                 "the Studio only opens files in its workspace") from None
        else:
            from ..data import find

            start = "example:" + find(args.file).name
    workspace = workspace or Path.cwd()
    if not workspace.is_dir():
        raise SylvaError(f"--workspace {workspace}: no such folder")
    kw = {}
    if args.max_modules is not None:
        kw["max_modules"] = max(1, args.max_modules)
    if args.time_cap is not None:
        kw["time_cap"] = max(0.1, args.time_cap)
    serve(workspace, port=args.port, start_file=start, limits=Limits(**kw),
          open_browser=not args.no_browser)
    return 0
