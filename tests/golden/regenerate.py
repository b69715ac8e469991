"""Regenerate the golden numbers: ``python tests/golden/regenerate.py [--only SECTION]``.

Run from the repository root. Sections: ``presets`` (a short run of every closedloop
preset, ~1 min), ``logs`` (the shipped-log analyses, ~20 s) and ``figures`` (a
``python -m paper_figures --quick`` run with one BLAS thread, several minutes;
``--quick-out DIR`` reads an existing quick run's folder instead, which must have been
made with one BLAS thread too: ``OPENBLAS_NUM_THREADS=1 python -m paper_figures
--quick``). ``fig5`` (Figure 5 at the paper's settings, ``python -m paper_figures
--only 5`` with one BLAS thread, a few minutes; ``--fig5-out DIR`` reads such a run's
folder). ``--out DIR`` writes the JSON files there instead of over the references in
``tests/golden/``; ``--compare`` prints the largest relative difference from the
references, the numbers beyond the tolerance and the largest move of each tolerance
class (``golden_numbers.tolerance``: to compare two machines, or a build of this one
under ``NUMBA_CPU_NAME=generic OPENBLAS_CORETYPE=Sandybridge``, docs/TESTING.md).

A regenerated reference goes in the same commit as the change that moved it, with the
reason in the commit message (docs/TESTING.md, "Golden numbers").
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

import golden_numbers as g  # noqa: E402


def _quick_run(out: Path) -> None:
    from paper_figures.__main__ import main

    # one BLAS thread, as the test suite's quick-run fixture (tests/paper_figures/conftest.py)
    with g.limit_blas_threads():
        if main(["--out", str(out), "--quick"]) != 0:
            raise SystemExit("regenerate: the quick paper_figures run failed")


def _fig5_run(out: Path) -> None:
    from paper_figures.__main__ import main

    # one BLAS thread, as the test's run (tests/paper_figures/test_golden_fig5_round51.py)
    with g.limit_blas_threads():
        if main(["--out", str(out), *g.FIG5_ARGS]) != 0:
            raise SystemExit("regenerate: the Figure 5 paper_figures run failed")


def compute(section: str, quick_out: Path | None, fig5_out: Path | None = None) -> dict:
    if section == "presets":
        return g.compute_presets()
    if section == "logs":
        return g.compute_logs()
    if section == "fig5":
        if fig5_out is not None:
            return g.figure_numbers(fig5_out)
        with tempfile.TemporaryDirectory() as tmp:
            _fig5_run(Path(tmp) / "fig5")
            return g.figure_numbers(Path(tmp) / "fig5")
    if quick_out is not None:
        return g.figure_numbers(quick_out)
    with tempfile.TemporaryDirectory() as tmp:
        _quick_run(Path(tmp) / "quick")
        return g.figure_numbers(Path(tmp) / "quick")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python tests/golden/regenerate.py",
                                     description=__doc__.splitlines()[0])
    parser.add_argument("--only", choices=g.SECTIONS, action="append",
                        help="section to regenerate (repeatable; default: all)")
    parser.add_argument("--quick-out", type=Path, default=None,
                        help="folder of an existing `python -m paper_figures --quick` run")
    parser.add_argument("--fig5-out", type=Path, default=None,
                        help="folder of an existing `python -m paper_figures --only 5` run")
    parser.add_argument("--out", type=Path, default=None,
                        help="write the JSON files here instead of tests/golden/")
    parser.add_argument("--compare", action="store_true",
                        help="print the largest relative difference from the references")
    args = parser.parse_args(argv)
    for section in args.only or g.SECTIONS:
        numbers = compute(section, args.quick_out, args.fig5_out)
        before = g.read(section) if g.path_of(section).exists() else None
        if args.out is not None:
            args.out.mkdir(parents=True, exist_ok=True)
            path = g.write(section, numbers, args.out / f"{section}.json")
        else:
            path = g.write(section, numbers)
        print(f"regenerate: wrote {path}")
        if args.compare and before is not None:
            worst, where = g.max_relative_difference(before, numbers)
            moved = g.differences(section, before, numbers, g.RTOL[section])
            print(f"regenerate: {section}: largest relative difference {worst:.3g} at "
                  f"{where or '-'}; {len(moved)} numbers beyond RTOL={g.RTOL[section]:g}")
            for m in moved[:20]:
                print("   ", m)
            for what, (move, key) in sorted(g.largest_moves(before, numbers,
                                                             g.RTOL[section]).items()):
                print(f"regenerate: {section}: largest move of {what or 'the rest'}: "
                      f"{move:.3g} at {key}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
