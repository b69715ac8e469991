"""Batch summary totals of logs in extreme units (round 26 PART b, issue 27).

Reference: numpy on a rescaled copy. ``rms_total`` and ``std_total`` are the
root-sum-squares of the per-mode RMS and standard deviation; for a log multiplied by
``s`` they are ``s`` times those of the unscaled log (computed with numpy's
``np.sqrt(np.mean(x**2, axis=0))`` / ``np.std`` at scale 1), to rounding. Before the
round the squares overflowed to inf at s = 1e300 and underflowed to 0 at s = 1e-300.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from modalinfo.batch.analyses import resolve_params, run_log_task
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


@pytest.mark.parametrize("scale", [1e300, 1e-300, 1.0])
def test_summary_totals_are_finite_and_scale_with_the_units(tmp_path, scale):
    base = np.random.default_rng(26).standard_normal((400, 4)) + [0.5, 0.0, -0.3, 0.1]
    rms_ref = np.sqrt(np.sum(np.mean(base**2, axis=0)))
    std_ref = np.sqrt(np.sum(np.std(base, axis=0) ** 2))
    log = ModalLog(base * scale, rate=1000.0, modes=[2, 3, 4, 5], units="rad")
    path = save(log, tmp_path / "scaled.npz")
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # no overflow warning either
        row = run_log_task({"path": str(path), "analysis": "summary",
                            "params": resolve_params("summary")})
    assert row["rms_total"] == pytest.approx(scale * rms_ref, rel=1e-9, abs=0.0)
    assert row["std_total"] == pytest.approx(scale * std_ref, rel=1e-9, abs=0.0)
