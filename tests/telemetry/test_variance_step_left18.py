"""The spread (variance-step) rule of the quality report (issue 27, left18-quality).

References, from outside the code: the uniform law of a valid p-value under the null
(``scipy.stats.kstest`` against ``uniform``) and the binomial law of the number of
stationary logs flagged (``scipy.stats.binom``); the ratio of the mean absolute
deviations from the median before and after the step, computed with numpy; the
construction of the inputs (a step of known size and frame; round 18 PART a's l11: a
``kaos_like`` log followed by itself with its 27 columns reversed).
"""

from __future__ import annotations

import numpy as np
from scipy import stats
from scipy.signal import lfilter

from modalinfo._stats import VARIANCE_ALPHA, variance_steps
from modalinfo.telemetry import assess_quality
from modalinfo.telemetry.synthetic.presets import kaos_like


def test_l11_columns_reversed_half_way_is_not_stationary():
    k = kaos_like(2000, seed=0).coeffs
    rep = assess_quality(np.vstack([k, k[:, ::-1]]))
    assert rep.stationary is False
    assert rep.level_steps == ()
    assert len(rep.variance_steps) >= 4 and rep.variance_judged == 27
    # every change point found lies near the cut at frame 2000
    assert all(abs(frame - 2000) < 250 for _, frame, _, _ in rep.variance_steps)
    text = rep.describe()
    assert text.count("the spread steps or drifts in") == 1
    assert f"{rep.variance_steps[0][0]} at frame {rep.variance_steps[0][1]}" in text
    row = rep.to_dict()
    assert row["variance_judged"] == 27
    assert row["variance_steps"].split(", ")[0] == (
        f"{rep.variance_steps[0][0]} {rep.variance_steps[0][1]}")


def test_known_step_found_at_its_frame_with_numpy_ratio():
    rng = np.random.default_rng(5)
    x = rng.standard_normal((2000, 5))
    x[1200:, 2] *= 2.0
    rep = assess_quality(x)
    assert rep.stationary is False
    assert [s[0] for s in rep.variance_steps] == ["col2"]
    label, frame, ratio, p = rep.variance_steps[0]
    assert abs(frame - 1200) <= 60 and p < VARIANCE_ALPHA / 5
    dev = np.abs(x[:, 2] - np.median(x[:, 2]))
    assert np.isclose(ratio, dev[frame:].mean() / dev[:frame].mean(), rtol=1e-9)
    assert 1.6 < ratio < 2.4
    calm = assess_quality(np.delete(x, 2, axis=1))
    assert calm.variance_steps == () and calm.stationary is True


def test_stationary_logs_flagged_within_the_binomial_bound():
    # 100 white logs of 1000 x 20, stated family-wise rate 1 %: P(>= 4 flagged) = 0.018
    rng = np.random.default_rng(20261130)
    hits = sum(bool(variance_steps(rng.standard_normal((1000, 20)))[0]) for _ in range(100))
    assert stats.binom.sf(hits - 1, 100, 0.01) > 0.01, hits


def test_p_values_uniform_under_the_null():
    # white and AR(1) 0.5 columns: a valid p-value is uniform (or conservative)
    rng = np.random.default_rng(7)
    for rho in (0.0, 0.5):
        e = rng.standard_normal((2000 + 500, 200))
        x = lfilter([1.0], [1.0, -rho], e, axis=0)[500:]
        found, judged = variance_steps(x, alpha=200.0)  # every judged column back
        assert judged == 200 and len(found) == 200
        p = np.array([v.p_value for v in found])
        # 200 values: 5 % below 0.05 has a binomial sd of 1.5 %
        assert np.mean(p < 0.05) < 0.05 + 3 * 0.0154
        assert stats.kstest(p, "uniform").pvalue > 1e-3


def test_a_few_glitched_frames_are_not_a_step():
    rng = np.random.default_rng(11)
    x = rng.standard_normal((1000, 20))
    x[[100, 500, 900]] = 100.0
    rep = assess_quality(x)
    assert rep.variance_steps == ()
    assert rep.glitch_frames.tolist() == [100, 500, 900]


def test_persistent_short_columns_not_judged():
    # AR(1) 0.95 over 200 frames: about 10 effective absolute deviations, not judged
    rng = np.random.default_rng(3)
    x = lfilter([1.0], [1.0, -0.95], rng.standard_normal((700, 10)), axis=0)[500:]
    found, judged = variance_steps(x)
    assert judged == 0 and found == []
