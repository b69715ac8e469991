"""The one ``python -m paper_figures --quick`` run that the quick-run tests share.

Session-scoped, so that ``test_main_quick.py`` (its table and sections),
``test_golden_figures.py`` (the golden numbers of its JSON files and report) and
``test_quick_read_back.py`` (its figures read back) all read the same run: there is
one quick run per test session. While it runs, every ``Figure.savefig`` is recorded
(file name -> the matplotlib Figure saved) and the closed-loop runs of Figures 2-4 are
kept, so that tests can read the saved figures' axes back and compare the drawn series
with the runs they name; the run itself is unchanged.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass, field
from pathlib import Path

import pytest


@dataclass
class QuickRun:
    out: Path
    figures: dict = field(default_factory=dict)   # file name -> matplotlib Figure
    runs: object = None                           # paper_figures.closedloop_runs result


@pytest.fixture(scope="session")
def quick_run(tmp_path_factory):
    import importlib.util
    import sys

    from matplotlib.figure import Figure

    from paper_figures import closedloop_runs
    from paper_figures.__main__ import main

    spec = importlib.util.spec_from_file_location(
        "golden_numbers", Path(__file__).resolve().parents[1] / "golden" / "golden_numbers.py")
    g = sys.modules.get("golden_numbers") or importlib.util.module_from_spec(spec)
    if "golden_numbers" not in sys.modules:
        sys.modules["golden_numbers"] = g
        spec.loader.exec_module(g)
    path = tmp_path_factory.mktemp("quick")
    run = QuickRun(out=path)
    savefig, compute = Figure.savefig, closedloop_runs.compute

    def recording_savefig(self, fname, *args, **kwargs):
        run.figures[Path(str(fname)).name] = self
        return savefig(self, fname, *args, **kwargs)

    def recording_compute(*args, **kwargs):
        run.runs = compute(*args, **kwargs)
        return run.runs

    mp = pytest.MonkeyPatch()
    mp.setattr(Figure, "savefig", recording_savefig)
    mp.setattr(closedloop_runs, "compute", recording_compute)
    # one BLAS thread: under `pytest -n auto` every core already runs a worker, and
    # OpenBLAS threads that wait for a busy core spin. Measured on 2 loaded cores
    # (2026-11-26): the whole run 167 s of CPU with OpenBLAS's default threads, 105 s
    # with one (Figure 1 49 -> 16 s, the closed-loop runs 69 -> 40 s). The tests read
    # the run's own outputs, so they hold for either; the golden numbers
    # (tests/golden/regenerate.py) are made with one thread too, and limit_blas_threads
    # loads every BLAS first (threadpoolctl limits only loaded libraries: 2 threads move
    # the NN runs' numbers).
    try:
        with g.limit_blas_threads():
            assert main(["--out", str(path), "--quick"]) == 0
    finally:
        mp.undo()
    return run


@contextlib.contextmanager
def saved_figures():
    """Record every ``Figure.savefig`` inside the block: yields {file name: Figure}.

    The figures are saved as usual; tests read their axes back afterwards.
    """
    from matplotlib.figure import Figure

    figures = {}
    savefig = Figure.savefig

    def recording(self, fname, *args, **kwargs):
        figures[Path(str(fname)).name] = self
        return savefig(self, fname, *args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(Figure, "savefig", recording)
        yield figures
