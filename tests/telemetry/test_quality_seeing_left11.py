"""The quality pass says when a log's seeing changes (issue 27, leftovers 11-seeing).

The rule (``modalinfo.telemetry.quality``): the AR(4) innovations are split into 8
contiguous blocks; the log is called non-stationary where the median over modes of
(largest / smallest 1.4826 MAD per block) exceeds ``stationarity_threshold`` of the
effective innovations per block. Which values are flagged does not change.

References (outside the code under test):
- constructed logs whose law is known: a variance step x7.4 halfway (r0 0.1 -> 0.03 m:
  ``(0.1 / 0.03)^(5/3)``; Kolmogorov phase scales as ``r0^(-5/6)``, so multiplying the
  second half of a stationary log by ``sqrt(7.4)`` is that seeing change) and iid
  Gaussian values whose sd ramps from 1 to 3 (adversarial round 11 PART a rows
  q-seeing-x7.4, c-quality-ramp-iid): noted; seeded stationary AR(1) logs
  (``scipy.signal.lfilter``, burnt in) of several rho, ``kaos_like`` open-loop logs and the
  shipped data/*.npz logs: not noted;
- the MAD's sampling law, by simulation independent of the code: the 99th percentile of
  (max / min) of 8 independent 1.4826 MADs of n Gaussian values, against the threshold.
The tests take ~5 s together.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.signal import lfilter

from modalinfo.io import load
from modalinfo.telemetry.quality import assess_quality, stationarity_threshold
from modalinfo.telemetry.synthetic import kaos_like

DATA = Path(__file__).resolve().parents[2] / "data"
STEP = (0.1 / 0.03) ** (5.0 / 3.0)  # variance ratio of r0 0.1 -> 0.03 m: 7.4


def _ar1(seed: int, n: int, m: int, rho: float) -> np.ndarray:
    g = np.random.default_rng(seed).standard_normal((n + 500, m)) * math.sqrt(1 - rho**2)
    return lfilter([1.0], [1.0, -rho], g, axis=0)[500:]


@pytest.mark.parametrize("rho", [0.0, 0.99, 0.999])
def test_variance_step_is_noted(rho):
    x = _ar1(1, 4000, 20, rho)
    x[2000:] *= math.sqrt(STEP)
    report = assess_quality(x)
    assert report.stationary is False
    # the blocks on each side hold one scale each: the ratio is the step's sqrt(7.4)
    assert 0.8 * math.sqrt(STEP) < report.scale_ratio < 1.25 * math.sqrt(STEP)
    assert "seeing not steady?" in report.note
    assert "1 % false-flag rate assumes a stationary log" in report.describe()
    d = report.to_dict()
    assert d["stationary"] is False and d["note"] == report.note
    assert d["scale_ratio"] == pytest.approx(report.scale_ratio)


def test_open_loop_seeing_step_is_noted():
    log = kaos_like(4000, closed_loop=False, seed=3)
    x = np.array(log.coeffs)
    x[2000:] *= math.sqrt(STEP)
    report = assess_quality(x)
    assert report.stationary is False


def test_sd_ramp_is_noted():
    rng = np.random.default_rng(5)
    x = rng.standard_normal((4000, 10)) * np.linspace(1.0, 3.0, 4000)[:, None]
    report = assess_quality(x)
    # first and last eighths have sd about 1.125 and 2.875: a ratio near 2.5
    assert report.stationary is False
    assert 2.0 < report.scale_ratio < 3.0


@pytest.mark.parametrize("rho", [0.0, 0.5, 0.9, 0.99, 0.999])
def test_stationary_ar1_is_not_noted(rho):
    for seed in range(3):
        report = assess_quality(_ar1(10 + seed, 4000, 10, rho))
        assert report.stationary is True, (rho, seed, report.scale_ratio)
        assert report.note == ""
        assert "seeing" not in report.describe()
        assert "note" not in report.to_dict()


@pytest.mark.parametrize("name", ["kaos_like_open_loop.npz", "kaos_like_closed_loop.npz",
                                  "kaos_closedloop.npz"])
def test_shipped_logs_are_not_noted(name):
    report = assess_quality(load(DATA / name))
    assert report.stationary is True
    assert report.scale_ratio < 1.3


@pytest.mark.parametrize("n", [4000, 8000])
def test_kaos_like_open_loop_is_not_noted(n):
    for seed in range(2):
        assert assess_quality(kaos_like(n, closed_loop=False, seed=seed)).stationary is True


def test_threshold_follows_the_mad_sampling_law():
    # 99th percentile of max/min of 8 independent 1.4826 MADs of 100 Gaussian values
    g = np.random.default_rng(20261129).standard_normal((4000, 8, 100))
    mad = np.median(np.abs(g - np.median(g, axis=2, keepdims=True)), axis=2)
    q99 = float(np.quantile(mad.max(axis=1) / mad.min(axis=1), 0.99))
    thr = stationarity_threshold(100)
    # the threshold's log is the law's 99 % range: within 10 %, and not below it by more
    # than the Monte-Carlo error (a 10 % wrong constant fails one side)
    assert abs(math.log(thr) / math.log(q99) - 1.0) < 0.08
    # long logs: no smaller change than x1.5 is noted; short blocks: no judgement
    assert stationarity_threshold(1e6) == 1.5
    assert stationarity_threshold(99) == math.inf


def test_too_few_frames_per_block_gives_no_judgement():
    rng = np.random.default_rng(2)
    x = rng.standard_normal((300, 5))
    x[150:] *= 3.0
    report = assess_quality(x)
    # the scale rule does not judge 300 frames (threshold inf); since left18-quality the
    # spread rule (absolute deviations) finds this x3 step, and stationary is False by it
    assert stationarity_threshold(report.effective_frames / 8) == math.inf
    assert "seeing" not in report.describe()
    assert [s[0] for s in report.variance_steps] == [f"col{j}" for j in range(5)]
    assert report.stationary is False and report.to_dict()["stationary"] is False


def test_info_prints_the_caveat(tmp_path, capsys):
    from modalinfo.cli import main
    from modalinfo.io import save
    from modalinfo.telemetry import ModalLog

    x = _ar1(4, 4000, 5, 0.9)
    x[2000:] *= math.sqrt(STEP)
    steady = save(ModalLog(_ar1(4, 4000, 5, 0.9), rate=1000.0, units="rad"),
                  tmp_path / "steady.npz")
    changed = save(ModalLog(x, rate=1000.0, units="rad"), tmp_path / "changed.npz")
    assert main(["info", str(changed), "--quiet"]) == 0
    quality = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("quality")]
    assert len(quality) == 1 and "seeing not steady?" in quality[0]
    assert main(["info", str(steady), "--quiet"]) == 0
    assert "seeing" not in capsys.readouterr().out


def test_range_constant_is_the_studentized_range_of_8():
    # Stop 45: the constant read 5.09 (the tables' q(0.99; 9, inf)); scipy's studentized
    # range with infinite degrees of freedom is the range of 8 standard Gaussians
    from scipy.stats import studentized_range

    from modalinfo._stats import RANGE_99_OF_8

    assert RANGE_99_OF_8 == pytest.approx(studentized_range.ppf(0.99, 8, np.inf), abs=0.005)
