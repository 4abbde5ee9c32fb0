"""``liquidamp demo --out DIR``: the paper's case study, end to end."""

from __future__ import annotations

import sys
import time
from pathlib import Path


def register(sub) -> None:
    """Add the ``demo`` sub-command."""
    p = sub.add_parser(
        "demo",
        help="reproduce the paper's case study (Figs. 7-11) into DIR/index.html",
        description="Reproduce Titurus (2018) Figs. 7-11 with the full model: PNGs and an "
        "index.html with the first-harmonic dynamic stiffness of every case.",
    )
    p.add_argument("--out", default="liquidamp-demo", help="output directory (default %(default)s)")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    p.add_argument("--engine", choices=("compiled", "python"), default="compiled",
                   help="integration engine (default %(default)s; python is the reference)")
    p.set_defaults(func=run)


def run(args) -> int:
    """Run the demo; return the exit code."""
    from liquidamp.analysis.casestudy import run_case_study, write_case_study

    start = time.perf_counter()

    def progress(msg: str) -> None:
        if not args.quiet:
            print(f"[{time.perf_counter() - start:6.1f} s] {msg}", file=sys.stderr)

    from liquidamp.options import SolverOptions

    out = Path(args.out)
    study = run_case_study(options=SolverOptions(engine=args.engine), progress=progress)
    index = write_case_study(study, out)
    progress(f"wrote {index}")
    print(index)
    return 0
