"""Adversarial round 10, PART b (command lines, files, environment): the fixed rows.

References, all outside the code under test: the count of MI estimates an ordering
makes (a bootstrap replicate re-estimates each of the M - 1 steps and its swapped rival;
``--stability W`` orders T // W windows and the whole log for 3 seeds); the histogram
bias rule of docs (``n >= k^d`` with ``k >= 4`` bins per axis: 10 samples give 3 bins);
the aotpy-built files of each test (a loop without mode images records no modes; a
FRAMERATE card of 1000 Hz beside 2 kHz timestamps); the arithmetic of rates (2000 Hz
and 2000 (1 + 1.1e-9) Hz differ in the 10th significant digit); rows of
docs/ADVERSARIAL.md "Round 10 PART b". Each test fails on the code before its fix.
"""

from __future__ import annotations

import argparse

import pytest

from modalinfo.cli.cmd_reorder import check_mi_time
from modalinfo.common.cli import CommandError

from .conftest import exit_code, write_small_log


def _args(**kw):
    base = dict(estimator="histogram", budget=200_000, frame=None, pupil_pixels=64,
                resamples=0, stability=None)
    return argparse.Namespace(**{**base, **kw})


class _Log:
    def __init__(self, n_frames, n_modes):
        self.n_frames, self.n_modes = n_frames, n_modes


# ------------------------------------------------------ B13: bootstrap replicates counted
def test_a_bootstrap_that_cannot_finish_in_an_hour_is_refused():
    # 300 modes, 600,000 samples, 1000 replicates: each replicate makes >= 2 M - 3 = 597
    # histogram estimates at >= 2e-8 s per sample (the module's floor), >= 2 h in all;
    # one estimate per replicate was counted before (19 s: accepted)
    with pytest.raises(CommandError, match="h of CPU"):
        check_mi_time(_args(budget=600_000, resamples=1000), _Log(200, 300))
    check_mi_time(_args(budget=600_000, resamples=0), _Log(200, 300))


# ---------------------------------------------------- R04: --stability windows counted
def test_stability_windows_are_counted_in_the_time_rule(monkeypatch):
    from modalinfo.ordering import cost

    # one ordering of 27 modes on 200,000 samples makes >= 52 estimates; --stability
    # 2000 on 4000 frames adds 2 window orderings and 3 seeds' whole-log orderings: a
    # limit of 1.5 orderings' time passes the first and refuses the second
    one = 52 * 200_000 * cost.MI_SECONDS_PER_SAMPLE["histogram"](200_000)
    monkeypatch.setattr(cost, "MAX_ORDERING_SECONDS", 1.5 * one)
    check_mi_time(_args(), _Log(4000, 27))
    with pytest.raises(CommandError, match="--stability 2000"):
        check_mi_time(_args(stability=2000), _Log(4000, 27))


# ------------------------------------------------- R08: too few samples for the MI rule
def test_a_budget_below_the_histogram_bias_rule_is_refused(tmp_path, capsys):
    log = write_small_log(tmp_path / "log.npz", 400)
    code = exit_code(["reorder", log, "--budget", 10, "--resamples", 0, "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "--budget 10" in err and "bins per axis" in err
    assert len(err.strip().splitlines()) == 1
    assert exit_code(["reorder", log, "--budget", 2000, "--resamples", 0, "--quiet",
                      "--pupil-pixels", 16]) == 0
