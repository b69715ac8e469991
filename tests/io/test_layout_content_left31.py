"""A log read transposed is named, not used silently (issue 27, left31-orient; round 31 b a25).

References: the lag-1 autocorrelation of each series from ``statsmodels.tsa.stattools.acf``
(the biased estimator, ``adjusted=False``), pooled and double-centred as written out
here with NumPy; the threshold from ``scipy.stats.norm.isf``; arrays written with
``numpy.save`` and ``astropy.io.fits`` (a FITS image in IDL order: NAXIS1 the frames,
numpy shape (modes, frames), no CTYPEn), built as seeded stationary AR(1) series with
``scipy.signal.lfilter``; the command line through ``python -m modalinfo`` (its stderr
as a user sees it).

Rates: under the rule's stated false-alarm probability ``LAYOUT_ALPHA`` = 1e-4 per log,
60 logs read the right way round flag one or more with probability <= 60e-4 = 0.006
(union bound); the transposed logs of the power test were flagged at margins >= 2.0
thresholds in 700 logs of benchmarks/bench_layout_left31.py (min margin over 20 logs
of each family and shape), so a miss here would be a change of the rule, not chance.
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from astropy.io import fits
from scipy.signal import lfilter
from scipy.stats import norm
from statsmodels.tsa.stattools import acf

ROOT = Path(__file__).resolve().parents[2]


def _ar1(frames: int, rhos, seed: int) -> np.ndarray:
    """(frames, modes) stationary AR(1) columns, sd falling as (n + 1)^(-11/6) (Noll-like)."""
    rhos = np.asarray(rhos, dtype=float)
    m = rhos.size
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((frames, m))
    j = np.arange(2, m + 2)
    n = np.floor((np.sqrt(8 * j - 7) - 1) / 2)
    x = np.empty((frames, m))
    for k, r in enumerate(rhos):
        z = e[:, k] * math.sqrt(1.0 - r * r)
        z[0] = e[0, k]
        x[:, k] = lfilter([1.0], [1.0, -r], z)
    return x * (n + 1.0) ** (-11.0 / 6.0)


def _pooled_reference(x: np.ndarray) -> float:
    """statsmodels' lag-1 of each column, weighted by its sum of squares."""
    power = (x ** 2).sum(axis=0)
    r = np.array([acf(x[:, k], nlags=1, adjusted=False, fft=False)[1]
                  for k in range(x.shape[1])])
    return float(r @ power / power.sum())


def test_statistics_are_pooled_lag1_of_the_double_centred_array():
    from modalinfo.telemetry.checks import LAYOUT_ALPHA, layout_lag1

    x = _ar1(400, np.linspace(0.3, 0.95, 30), seed=1) + np.linspace(0, 5, 30)  # offsets
    c = x - x.mean(axis=0)
    c -= c.mean(axis=1, keepdims=True)
    m0, m1, threshold = layout_lag1(x)
    assert m0 == pytest.approx(_pooled_reference(c), abs=1e-10)
    assert m1 == pytest.approx(_pooled_reference(c.T), abs=1e-10)
    assert threshold == pytest.approx(norm.isf(LAYOUT_ALPHA) / math.sqrt(30), rel=1e-12)


def test_no_false_alarm_on_stationary_logs_and_the_transposed_ones_are_found():
    from modalinfo.telemetry.checks import layout_doubt

    rng = np.random.default_rng(5)
    kept = found = 0
    cases = []
    for i in range(20):  # Noll-like persistence falling with the radial order
        rho0 = rng.uniform(0.5, 0.999)
        j = np.arange(2, 22)
        cases.append((_ar1(2000, rho0 ** (np.floor((np.sqrt(8 * j - 7) - 1) / 2) + 1.0),
                           seed=100 + i), True))
    for i in range(20):  # near-square, round 31 b a25's shape
        cases.append((_ar1(300, np.full(200, rng.uniform(0.5, 0.999)), seed=200 + i), True))
    for i in range(20):  # white: no data tells either way
        cases.append((_ar1(300, np.zeros(200), seed=300 + i), False))
    for x, persistent in cases:
        kept += layout_doubt(x) is not None
        flipped = layout_doubt(np.ascontiguousarray(x.T)) is not None
        found += flipped
        assert flipped == persistent
    assert kept == 0
    assert found == 40


def test_library_load_warns_once_records_and_obeys_the_hints(tmp_path):
    from modalinfo.batch.analyses import log_columns
    from modalinfo.io import LayoutWarning, load

    x = _ar1(300, np.full(200, 0.99), seed=7)  # 300 frames x 200 modes
    np.save(tmp_path / "mt.npy", x.T)  # stored modes x frames, as IDL / MATLAB would
    np.save(tmp_path / "tm.npy", x)
    with pytest.warns(LayoutWarning, match=r"--transpose") as caught:
        log = load(tmp_path / "mt.npy")
    assert len(caught) == 1
    assert log.coeffs.shape == (200, 300)  # read as stored: a warning, not a refusal
    assert "modes x frames" in log.metadata["layout"]["doubt"]
    assert "modes x frames" in log_columns(log)["layout_doubt"]  # batch's row says it
    # the caller's word or the right layout: no warning (warnings are errors here)
    assert load(tmp_path / "mt.npy", transpose=True).coeffs.shape == (300, 200)
    np.testing.assert_array_equal(load(tmp_path / "mt.npy", transpose=True).coeffs, x)
    assert load(tmp_path / "mt.npy", transpose=False).coeffs.shape == (200, 300)
    assert "layout" not in load(tmp_path / "tm.npy").metadata
    white = _ar1(300, np.zeros(200), seed=8)
    np.save(tmp_path / "white.npy", white.T)
    assert load(tmp_path / "white.npy").coeffs.shape == (200, 300)  # nothing tells


def _info(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT),
                                                       os.environ.get("PYTHONPATH", "")]))
    env.pop("PYTHONWARNINGS", None)
    return subprocess.run([sys.executable, "-m", "modalinfo", "info", "--quiet", *args],
                          capture_output=True, text=True, env=env, timeout=600)


def test_idl_fits_a25_end_to_end_through_info(tmp_path, capsys):
    from modalinfo.cli import main

    # round 31 PART b a25: 300 frames x 200 modes, NAXIS1 = frames, no CTYPEn
    x = _ar1(300, np.full(200, 0.99), seed=9)
    path = tmp_path / "sqMT.fits"
    fits.PrimaryHDU(x.T).writeto(path)
    assert fits.getheader(path)["NAXIS1"] == 300 and "CTYPE1" not in fits.getheader(path)
    p = _info(str(path))  # a subprocess: the warning as a user sees it on stderr
    assert p.returncode == 0, p.stderr
    assert "shape       200 frames x 300 modes" in p.stdout  # read as stored ...
    warned = [ln for ln in p.stderr.splitlines() if "modes x frames" in ln]
    assert len(warned) == 1, p.stderr  # ... and said once, in one line
    assert warned[0].startswith("modalinfo info: warning: 'sqMT.fits'")
    assert "--transpose" in warned[0] and "Traceback" not in p.stderr
    # the user's word: no warning (in this process warnings are errors)
    assert main(["info", "--quiet", str(path), "--transpose"]) == 0
    assert "shape       300 frames x 200 modes" in capsys.readouterr().out
    assert main(["info", "--quiet", str(path), "--no-transpose"]) == 0
    assert "shape       200 frames x 300 modes" in capsys.readouterr().out


def test_batch_rows_carry_the_doubt_and_batch_says_it_once(tmp_path, capsys):
    # each task reads the log (one per analysis): the warning was printed once per task
    from modalinfo.batch.analyses import resolve_params, run_log_task
    from modalinfo.cli.cmd_batch import layout_doubt_note

    x = _ar1(300, np.full(200, 0.99), seed=11)
    np.save(tmp_path / "mt.npy", x.T)
    np.save(tmp_path / "tm.npy", x)
    rows = [run_log_task({"path": str(tmp_path / name), "fmt": None, "hints": {},
                          "analysis": "summary", "params": resolve_params("summary")})
            for name in ("mt.npy", "tm.npy", "mt.npy")]  # no warning: errors here
    assert "modes x frames" in rows[0]["layout_doubt"] and "layout_doubt" not in rows[1]
    for row, name in zip(rows, ("mt.npy", "tm.npy", "mt.npy"), strict=True):
        row.update(status="ok", path=str(tmp_path / name))  # what the engine adds
    layout_doubt_note(rows)
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "1 log(s)" in err and "mt.npy" in err, err
    assert "--transpose" in err and "tm.npy" not in err
