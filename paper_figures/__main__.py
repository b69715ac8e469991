"""Regenerate every paper figure that the package can make, and write a report.

Usage::

    python -m paper_figures [--log data/kaos_like_closed_loop.npz] [--out out] [--overwrite]
                            [--only 1,2,3,4,5] [--quick] [--duration S] [--seed N]

Figures 1 and 5 analyse the modal log. Figures 2-4 draw closed-loop MCAO runs of the
paper's Table 1 (``closedloop`` preset ``table1``, one atmosphere, every predictor;
:mod:`paper_figures.closedloop_runs`), computed once and shared: 0.5 s of simulated time
by default (a few minutes on an idle 2-core machine, most of it training the paper's
neural net), or with ``--quick`` 0.2 s on a 5x5 field grid with the neural net trained
for 50 iterations (reduced settings for Figures 2-4 only; Figures 1 and 5 are unchanged).
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


def _parse_only(text: str | None) -> list[int]:
    numbers = [int(label.split()[-1]) for _, label, _ in FIGURES]
    if text is None:
        return numbers
    try:
        chosen = sorted({int(t) for t in text.split(",") if t.strip()})
    except ValueError:
        chosen = []
    if not chosen or any(c not in numbers for c in chosen):
        raise ValueError(f"--only must be a comma list of figure numbers "
                         f"{','.join(map(str, numbers))}; got '{text}'")
    return chosen


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
    parser.add_argument("--only", default=None,
                        help="comma-separated figure numbers to make (default: all)")
    parser.add_argument("--quick", action="store_true",
                        help="reduced closed-loop settings for Figures 2-4 (0.2 s, 5x5 field)")
    parser.add_argument("--duration", type=float, default=None,
                        help="simulated time of the Figures 2-4 runs [s] (default 0.5, "
                             "quick 0.2)")
    parser.add_argument("--seed", type=int, default=0,
                        help="atmosphere of the Figures 2-4 runs (default 0)")
    args = parser.parse_args(argv)

    try:
        only = _parse_only(args.only)
    except ValueError as exc:
        sys.stderr.write(f"paper_figures: error: {exc}\n")
        return 2
    if args.duration is not None and args.duration <= 0:
        sys.stderr.write(f"paper_figures: error: --duration must be > 0 s; got {args.duration:g}\n")
        return 2
    if args.seed < 0:
        sys.stderr.write(f"paper_figures: error: --seed must be >= 0; got {args.seed}\n")
        return 2
    chosen = [(name, label, title) for name, label, title in FIGURES
              if int(label.split()[-1]) in only]
    modules = [(importlib.import_module(f"paper_figures.{name}"), label, title)
               for name, label, title in chosen]
    needs_log = any(not getattr(m, "NEEDS_RUNS", False) for m, _, _ in modules)
    if needs_log and not args.log.is_file():
        sys.stderr.write(f"paper_figures: error: log file '{args.log}' does not exist\n")
        return 2
    report_path = args.out / "report.md"
    html_path = args.out / "report.html"
    outputs = [report_path, html_path] + [
        args.out / getattr(module, attr)
        for module, _, _ in modules
        for attr in ("FIGURE_NAME", "PDF_NAME", "JSON_NAME")
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
        f"Python {platform.python_version()}, {platform.machine()}."
        + (f" Input log of Figures 1 and 5: `{args.log}`." if needs_log else "") + "\n",
    ]
    runs = None
    for module, label, title in modules:
        start = time.perf_counter()
        if getattr(module, "NEEDS_RUNS", False) and runs is None:
            from paper_figures import closedloop_runs

            print(f"[paper_figures] closed-loop runs for Figures 2-4"
                  f"{' (quick)' if args.quick else ''} ...", flush=True)
            runs = closedloop_runs.compute(quick=args.quick, duration=args.duration,
                                           seed=args.seed)
            elapsed = time.perf_counter() - start
            print(f"[paper_figures] closed-loop runs done in {elapsed:.1f} s", flush=True)
            sections.append(closedloop_runs.report_section(runs, elapsed))
            start = time.perf_counter()
        print(f"[paper_figures] {label}: {title} ...", flush=True)
        if getattr(module, "NEEDS_RUNS", False):
            text = module.make(args.out, runs)
        else:
            text = module.make(args.out, args.log)
        elapsed = time.perf_counter() - start
        print(f"[paper_figures] {label} done in {elapsed:.1f} s", flush=True)
        sections.append(text.rstrip() + f"\n\n_({label} made in {elapsed:.1f} s.)_\n")
    from paper_figures._html import report_html

    text = "\n".join(sections)
    report_path.write_text(text, encoding="utf-8")
    html_path.write_text(report_html(text, args.out), encoding="utf-8")
    print(f"[paper_figures] report written to {report_path} and {html_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
