"""Regenerate every paper figure that the package can make, and write a report.

Usage::

    python -m paper_figures [--log data/kaos_like_closed_loop.npz] [--out out] [--overwrite]

Figures 2-4 of the paper come from the closed-loop MCAO simulator (``closedloop``),
which is the next milestone; the report says so instead of drawing them.
"""

from __future__ import annotations

import argparse
import importlib
import platform
import sys
import time
from pathlib import Path

from paper_figures import FIGURES

DEFAULT_LOG = Path(__file__).resolve().parent.parent / "data" / "kaos_like_closed_loop.npz"

PENDING = """## Figures 2, 3 and 4: not yet regenerated

Figures 2 (peak Strehl ratio vs time), 3 (power spectra of the SR) and 4 (time-averaged
SR maps and the corrected field of view) come from closed-loop MCAO simulations of the
paper's Table 1. They need the `closedloop` simulator, which is the next milestone of the
roadmap and is not built yet, so this report does not draw them.
"""


def main(argv: list[str] | None = None) -> int:
    """Make every figure and ``report.md``; return the exit status."""
    parser = argparse.ArgumentParser(
        prog="python -m paper_figures", description=__doc__.split("\n")[1]
    )
    parser.add_argument(
        "--log", type=Path, default=DEFAULT_LOG,
        help="closed-loop modal log to analyse (default: the shipped KAOS-like log)",
    )
    parser.add_argument(
        "--out", type=Path, default=Path("out"), help="output directory (default: out)"
    )
    parser.add_argument("--overwrite", action="store_true",
                        help="replace figures and report already in the output directory")
    args = parser.parse_args(argv)

    if not args.log.is_file():
        sys.stderr.write(f"paper_figures: error: log file '{args.log}' does not exist\n")
        return 2
    report_path = args.out / "report.md"
    modules = [(importlib.import_module(f"paper_figures.{name}"), label, title)
               for name, label, title in FIGURES]
    outputs = [report_path] + [
        args.out / getattr(module, attr)
        for module, _, _ in modules
        for attr in ("FIGURE_NAME", "JSON_NAME")
        if hasattr(module, attr)
    ]
    existing = [path for path in outputs if path.exists()]
    if existing and not args.overwrite:
        sys.stderr.write(
            f"paper_figures: error: '{existing[0]}' exists; pass --overwrite to replace it\n"
        )
        return 2
    args.out.mkdir(parents=True, exist_ok=True)

    sections = [
        "# modalinfo: regenerated figures of Stangalini et al., LOST MCAO simulations\n",
        f"Input log: `{args.log}`. Python {platform.python_version()}, {platform.machine()}.\n",
    ]
    for module, label, title in modules:
        start = time.perf_counter()
        print(f"[paper_figures] {label}: {title} ...", flush=True)
        text = module.make(args.out, args.log)
        elapsed = time.perf_counter() - start
        print(f"[paper_figures] {label} done in {elapsed:.1f} s", flush=True)
        sections.append(text.rstrip() + f"\n\n_({label} made in {elapsed:.1f} s.)_\n")
    sections.append(PENDING)
    report_path.write_text("\n".join(sections), encoding="utf-8")
    print(f"[paper_figures] report written to {report_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
