"""``sylva batch``: a plan of plants × seeds × ages × sweeps × cameras, on the Dask road.

Examples::

    sylva batch plan.toml -o out/                    # a local cluster over the cores
    sylva batch plan.toml -o out/ --workers 1        # in this process
    sylva batch plan.toml -o /shared/out --scheduler tcp://head:8786

Every item is grown once, exported in the plan's formats and rendered from each of its
cameras; ``out/manifest.parquet`` lists every file with its inputs, counts and timing.
"""

from __future__ import annotations

import sys
from pathlib import Path

from ..errors import SylvaError


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "batch",
        help="grow, export and render a plan of plant variants (Dask)",
        description="Run a batch plan (TOML: [[plant]] entries with source, seeds, steps, "
                    "sweep, cameras) as Dask tasks; write the assets, the renders and "
                    "manifest.parquet into OUT.",
    )  # fmt: skip
    p.add_argument("plan", metavar="PLAN.toml", help="the batch plan")
    p.add_argument("-o", "--output", dest="out", required=True, metavar="OUT",
                   help="output folder")
    p.add_argument("--workers", type=int, default=None,
                   help="worker processes of the local Dask cluster (default: all cores)")
    p.add_argument("--scheduler", metavar="tcp://HOST:PORT", default=None,
                   help="run on an existing Dask cluster (default $SYLVA_SCHEDULER)")
    p.add_argument("--labels", action="store_true",
                   help="also write, for every render, a per-organ instance mask (16-bit "
                        "PNG), its depth (metres along the view axis: float32 .npy and "
                        "16-bit .png, near/far in the manifest) and COCO annotations")  # fmt: skip
    p.add_argument("--quiet", action="store_true", help="no progress output")
    p.set_defaults(func=run)


def run(args) -> int:
    from ..batch import parse_plan, run_batch

    path = Path(args.plan)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise SylvaError(f"cannot read the plan {str(path)!r}: {exc.strerror}") from None
    plan = parse_plan(text, str(path), base=path.parent)
    info = run_batch(plan, args.out, scheduler=args.scheduler, workers=args.workers,
                     progress=not args.quiet, labels=args.labels)  # fmt: skip
    if not args.quiet:
        print(f"wrote {info['files']} files for {info['items']} items; manifest "
              f"{info['manifest']}", file=sys.stderr)  # fmt: skip
    return 0
