"""Every command's pre-work memory estimate covers the peak it precedes (issue 27, left31-estimate).

``reorder``, ``forecast``, ``select`` and ``info`` refuse before the work what their
estimate says cannot fit; the estimate left out the log-quality pass every command runs
(``reorder`` of a 10^6 x 50 log: 57 MiB estimated, 136 MiB peak; ``info`` had none).
Here the estimate is the largest ``need`` any ``check_memory`` of the run was asked
about (the refusal compares exactly that with the memory available), and the reference
is the measured peak: ``tracemalloc``'s peak of numpy's and Python's allocations during
the command (deterministic counts, no timing), after a first run on a small log has
imported every module and compiled numba's kernels (the MAD's simulated law, which a
command computes once, is cleared before each run). Each command on 8 seeded AR(1)
log shapes (NPY files, read whole: small files are not memory-mapped): estimate >=
peak, and <= 3 x the peak (small logs under tight limits still run). ``batch``: the
per-log check before the pass against ``run_log_task``'s peak (summary analysis). Each
estimate was below its peak before this change (0.3-42 MiB for peaks of 9-74 MiB for
the commands whose estimate counted only their own arrays; none at all for ``info`` and
``batch``). And a pass that cannot fit (memory available between the old checks and
the pass's estimate) is refused in one line, exit 2, naming the pass (before: run, or
for ``select`` refused for its own candidates).
"""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

import modalinfo.cli.shared as shared
from modalinfo.cli import cmd_forecast, cmd_reorder, cmd_select, main
from modalinfo.telemetry import quality

SHAPES = [(300, 50), (1000, 5), (1000, 60), (2000, 20), (3000, 40), (5000, 10),
          (10_000, 5), (20_000, 20)]


def _write(path, frames: int, modes: int) -> None:
    rng = np.random.default_rng(frames + modes)
    x = rng.standard_normal((frames, modes))
    for t in range(1, frames):  # AR(1), rho 0.6
        x[t] += 0.6 * x[t - 1]
    np.save(path, x)


def _argv(command: str, path, out) -> list[str]:
    base = [str(path), "--rate", "1000", "--in-units", "rad"]
    return {
        "info": ["info", *base],
        "reorder": ["reorder", *base, "--method", "variance", "--resamples", "0",
                    "--pupil-pixels", "32"],
        "forecast": ["forecast", *base, "--predictors", "linear", "--horizon", "2",
                     "--quiet", "--overwrite", "--out", str(out)],
        "select": ["select", *base, "--target", "Z3", "--max-lag", "2", "--surrogates",
                   "19", "--no-intervals", "--method", "gaussian"],
    }[command]


def _measure(monkeypatch, argv: list[str]) -> tuple[int, float]:
    needs: list[float] = []
    for module in (shared, cmd_reorder, cmd_forecast, cmd_select):
        if not hasattr(module, "check_memory"):  # it checks through shared's only
            continue
        original = module.check_memory

        def record(need, what, fix, _original=original):
            needs.append(float(need))
            return _original(need, what, fix)

        monkeypatch.setattr(module, "check_memory", record)
    quality._mad_law.cache_clear()  # a command pays the MAD's law once: cold
    tracemalloc.start()
    try:
        code = main(argv)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert code == 0
    return peak, max(needs, default=0.0)


@pytest.mark.parametrize("command", ["info", "reorder", "forecast", "select"])
def test_estimate_covers_the_measured_peak(tmp_path, monkeypatch, capsys, command):
    _write(tmp_path / "warm.npy", 200, 6)
    assert main(_argv(command, tmp_path / "warm.npy", tmp_path / "w")) == 0  # imports
    rows = []
    for frames, modes in SHAPES:
        path = tmp_path / f"l{frames}x{modes}.npy"
        _write(path, frames, modes)
        peak, estimate = _measure(monkeypatch, _argv(command, path, tmp_path / "o"))
        rows.append((frames, modes, peak, estimate))
        monkeypatch.undo()
    capsys.readouterr()
    text = "; ".join(f"{t}x{m}: {e / 2**20:.1f}/{p / 2**20:.1f} MiB" for t, m, p, e in rows)
    for frames, modes, peak, estimate in rows:
        assert estimate >= peak, f"{command} {frames} x {modes}: {text}"
        assert estimate <= 3 * peak, f"{command} {frames} x {modes}: {text}"


def test_batch_per_log_estimate_covers_the_task_peak(tmp_path, monkeypatch):
    from argparse import Namespace

    from modalinfo.batch import analyses
    from modalinfo.common import memory

    def task(path):
        return {"path": str(path), "fmt": None, "hints": {"rate": 1000.0, "units": "rad"},
                "analysis": "summary", "params": analyses.resolve_params("summary")}

    _write(tmp_path / "warm.npy", 200, 6)
    analyses.run_log_task(task(tmp_path / "warm.npy"))  # imports, numba
    for frames, modes in SHAPES:
        path = tmp_path / f"l{frames}x{modes}.npy"
        _write(path, frames, modes)
        log = np.load(path)  # read whole (small): the task's log is in memory
        estimate = shared.quality_need(log=_Shape(frames, modes), args=Namespace(),
                                       resident=log.nbytes)
        quality._mad_law.cache_clear()
        tracemalloc.start()
        try:
            analyses.run_log_task(task(path))
            peak = tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()
        assert peak <= estimate <= 3 * peak, (frames, modes, peak, estimate)
    # and a task whose pass cannot fit is refused before it (an error row names it)
    monkeypatch.setattr(memory, "usable_memory_bytes", lambda: 1e6)
    with pytest.raises(MemoryError, match="log-quality pass"):
        analyses.run_log_task(task(tmp_path / "l300x50.npy"))


class _Shape:
    """A log's shape, as ``quality_need`` reads it."""

    def __init__(self, frames: int, modes: int) -> None:
        self.n_frames, self.n_modes = frames, modes


@pytest.mark.parametrize("command", ["info", "reorder", "forecast", "select"])
def test_a_pass_that_cannot_fit_is_refused_in_one_line(tmp_path, monkeypatch, capsys,
                                                       command):
    # 2000 x 20: 0.3 MB of log, its 3 copies 1 MB, forecast's evaluation 2.6 MB (the old
    # checks pass under 4 MB), the quality pass ~20 MiB (measured 7.5 MiB, above)
    _write(tmp_path / "l.npy", 2000, 20)
    monkeypatch.setattr(shared, "memory_available", lambda: 4e6)
    assert main(_argv(command, tmp_path / "l.npy", tmp_path / "o")) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert "log-quality pass" in err and "needs about" in err, err
    assert not (tmp_path / "o").exists()  # forecast wrote nothing
