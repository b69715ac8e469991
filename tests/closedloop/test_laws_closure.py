"""Loop-closure detection on synthetic Strehl histories whose closure is known in advance.

References (computed in the test from the documented rule, not from closedloop's code):
- the rule of ``closedloop/result.py``'s docstring: the closure is the first frame from
  which the SR peak stays for 5 ms at or above the floor ``median - 3 sigma`` of the
  run's second half, ``sigma`` the robust standard deviation ``MAD / Phi^-1(3/4)``
  (``Phi^-1`` from scipy: 1 / 0.6745 = 1.4826, the consistency constant of the MAD for a
  Gaussian);
- a ramp ``S(k) = S_inf - dS exp(-(k - k0) / tau)`` from frame ``k0`` whose second half
  alternates ``S_inf +- delta`` (median ``S_inf``, MAD ``delta`` exactly) crosses that
  floor at ``k0 + tau ln(dS / (3 * 1.4826 * delta))``: the closure is the first whole
  frame after it (a 10 % error in the 3 or the 1.4826 moves it by ``tau ln 1.1`` = 2.9
  frames at tau = 30);
- a step with Gaussian noise closes within the 5-ms window after the step; dips planted
  just inside and just outside the window pin its length ``round(5 ms / T)`` frames;
- a series with no step (or a step in the second half) is "did not close".
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from closedloop import presets
from closedloop.result import SimulationResult

#: 1 / Phi^-1(3/4): the MAD's consistency constant for a Gaussian (outside reference)
MAD_TO_SIGMA = 1.0 / stats.norm.ppf(0.75)
N_SIGMA = 3.0


def _config(time_step):
    cfg = presets.kaos()
    loop = cfg.loop.__class__(time_step=time_step, integration_time=time_step,
                              delay=time_step / 2.0, gain=0.4)
    return cfg.replace(loop=loop)


def _result(cfg, sr):
    sr = np.asarray(sr, dtype=float)
    n_dir = cfg.field.n_points ** 2
    # the SR peak is the maximum over the field: the other directions are lower
    v = -np.log(sr)[:, None] * np.linspace(1.0, 1.5, n_dir)[None, :]
    times = (np.arange(sr.size) + 1) * cfg.loop.time_step
    return SimulationResult(config=cfg, seed=0, predictor="none", times=times,
                            directions=np.zeros((n_dir, 2)), residual_variance=v, logs={},
                            elapsed=1.0, version="test")


def _alternating(n, centre, delta):
    return centre + delta * np.where(np.arange(n) % 2 == 0, 1.0, -1.0)


@pytest.mark.parametrize("tau,delta", [(30.0, 0.004), (12.0, 0.01)])
def test_ramp_closes_where_it_crosses_the_robust_floor(tau, delta):
    cfg = _config(1e-3)
    n, k0, s0, s_inf = 400, 10, 0.05, 0.6
    k = np.arange(n)
    sr = np.where(k < k0, s0, s_inf - (s_inf - s0) * np.exp(-(k - k0) / tau))
    sr[n // 2:] = _alternating(n - n // 2, s_inf, delta)
    crossing = k0 + tau * math.log((s_inf - s0) / (N_SIGMA * MAD_TO_SIGMA * delta))
    # the crossing is not within rounding of a whole frame (else the test rests on luck)
    assert 0.05 < crossing - math.floor(crossing) < 0.95
    expected = math.ceil(crossing)
    assert expected < n // 2
    r = _result(cfg, sr)
    assert r.closure_index == expected
    assert r.closure_time == pytest.approx((expected + 1) * 1e-3)
    assert r.loop_status == "closed"


@pytest.mark.parametrize("time_step", [1e-3, 0.5e-3])
def test_noisy_step_closes_within_the_window(time_step):
    cfg = _config(time_step)
    window = round(5e-3 / time_step)
    rng = np.random.default_rng(3)
    n, k0 = 600, 40
    sr = np.concatenate([np.full(k0, 0.05), 0.6 + 0.01 * rng.standard_normal(n - k0)])
    r = _result(cfg, sr)
    assert k0 <= r.closure_index <= k0 + window
    assert r.closed


@pytest.mark.parametrize("time_step", [1e-3, 0.5e-3])
def test_window_is_five_milliseconds(time_step):
    cfg = _config(time_step)
    window = round(5e-3 / time_step)
    n, k0, s_inf, delta = 400, 20, 0.6, 0.002
    floor = s_inf - N_SIGMA * MAD_TO_SIGMA * delta
    base = np.concatenate([np.full(k0, 0.05), _alternating(n - k0, s_inf, delta)])
    # a dip just below the floor at k0 + 2: the closure is after it
    first = base.copy()
    first[k0 + 2] = floor - 0.2 * delta
    assert _result(cfg, first).closure_index == k0 + 3
    # ... a dip just above the floor does not count
    inside = base.copy()
    inside[k0 + 2] = floor + 0.2 * delta
    assert _result(cfg, inside).closure_index == k0
    # a second dip right after a clean window of `window` frames leaves the closure at
    # k0 + 3; one frame earlier (inside the window) pushes it past the second dip
    after = first.copy()
    after[k0 + 3 + window] = floor - 0.2 * delta
    assert _result(cfg, after).closure_index == k0 + 3
    within = first.copy()
    within[k0 + 2 + window] = floor - 0.2 * delta
    assert _result(cfg, within).closure_index == k0 + 3 + window


def test_no_step_does_not_close():
    cfg = _config(1e-3)
    rng = np.random.default_rng(5)
    flat = _result(cfg, 0.3 + 0.01 * rng.standard_normal(400))
    assert not flat.closed and not flat.diverged
    assert flat.loop_status.startswith("did not close")
    # a step in the second half: the steady band is not reached in the first half
    late = np.concatenate([np.full(260, 0.05), 0.6 + 0.01 * rng.standard_normal(140)])
    r = _result(cfg, late)
    assert not r.closed
    assert r.loop_status.startswith("did not close")


def test_headline_means_start_at_the_known_closure():
    # the ramp of the first test: its closure frame is known in closed form, so the
    # "after closure" means are the plain means of the synthetic series from there
    cfg = _config(1e-3)
    n, k0, s0, s_inf, tau, delta = 400, 10, 0.05, 0.6, 30.0, 0.004
    k = np.arange(n)
    sr = np.where(k < k0, s0, s_inf - (s_inf - s0) * np.exp(-(k - k0) / tau))
    sr[n // 2:] = _alternating(n - n // 2, s_inf, delta)
    start = math.ceil(k0 + tau * math.log((s_inf - s0) / (N_SIGMA * MAD_TO_SIGMA * delta)))
    r = _result(cfg, sr)
    s = r.summary()
    assert s["closure_time_s"] == pytest.approx((start + 1) * 1e-3)
    assert s["strehl_peak_mean"] == pytest.approx(float(sr[start:].mean()), rel=1e-12)
    n_dir = cfg.field.n_points ** 2
    field = np.exp(np.log(sr)[:, None] * np.linspace(1.0, 1.5, n_dir)[None, :])
    assert s["strehl_field_mean"] == pytest.approx(float(field[start:].mean()), rel=1e-12)


def test_strehl_peak_spectrum_is_a_density_of_the_sr_variance():
    # Parseval: the one-sided density integrates to the variance; a sinusoid of
    # amplitude A at f0 (a whole number of cycles per Welch segment) carries A^2 / 2 at f0
    cfg = _config(1e-3)
    n, k0, f0, amp = 2048, 20, 125.0, 0.02
    t = np.arange(n) * 1e-3
    rng = np.random.default_rng(8)
    sr = 0.6 + amp * np.sin(2 * np.pi * f0 * t) + 0.001 * rng.standard_normal(n)
    sr[:k0] = 0.05
    r = _result(cfg, sr)
    freqs, psd = r.strehl_peak_spectrum(start=k0 + 12)
    df = freqs[1] - freqs[0]
    assert df == pytest.approx(1000.0 / 256)
    x = sr[k0 + 12:]
    assert float(np.sum(psd) * df) == pytest.approx(float(x.var()), rel=0.03)
    assert freqs[np.argmax(psd)] == pytest.approx(f0)
    band = np.abs(freqs - f0) <= 2 * df
    assert float(np.sum(psd[band]) * df) == pytest.approx(amp ** 2 / 2, rel=0.03)
