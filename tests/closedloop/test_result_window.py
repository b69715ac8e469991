"""One averaging window per result: every "after closure" average of a run starts at one frame.

References (outside the code): residual-variance histories built here whose loop status
and window are known by construction (a closed step, an SR peak that never rose, whose
detected "closure" is frame 0, a run whose SR peak reaches no steady state, a diverged
one); numpy means over the frames of the documented window (docs/CLOSEDLOOP.md, "One
averaging window per run": the closure if the loop closed, the second half ``T // 2``
if it did not close, is still converging or diverged, frame 0 in open loop); the area
where a bilinear interpolation of a 3x3 map with centre 0.9 and edges 0.1 exceeds 0.3,
integrated analytically (``4 (3/4 - ln(4) / 4)`` cells); scipy's Welch spectrum of the
window's SR peak; and, for the error budget, a tiny simulated loop whose gain is too low
to correct (it does not close; its detected "closure" is frame 0), whose budget must
average the probed frames of its second half against numpy's mean of its own residual.
Fast: hand-built results, one 12-frame loop (~1-2 s of CPU).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import signal

from .conftest import small
from .test_result_views import T, _config, _result, _step

N = 100  # frames of the hand-built histories: the second half starts at frame 50
SR_CENTRE, SR_EDGE = 0.9, 0.1


def _diameter(edge: float, centre: float = SR_CENTRE, threshold: float = 0.3) -> float:
    """Equivalent diameter [arcmin] where the bilinear 3x3 map over 60" exceeds ``threshold``.

    Centre ``centre``, the 8 others ``edge``: in each of the four 30" cells the map is
    ``edge + (centre - edge) (1 - u)(1 - v)``, above the threshold where ``(1 - u)(1 - v)
    > a = (threshold - edge) / (centre - edge)``: an area ``1 - a + a ln a`` of the cell.
    """
    a = (threshold - edge) / (centre - edge)
    area = 4 * (1 - a + a * math.log(a)) * 30.0 ** 2
    return 2 * math.sqrt(area / math.pi) / 60.0


def _never_rose(n: int = N) -> np.ndarray:
    """(n, 9): the centre at SR 0.9 throughout, the 8 others at SR 0.02 then 0.1.

    The SR peak (the centre) is flat, so its band holds the open loop: the detected
    "closure" is frame 0, before any command, and the field-mean residual (3.49 rad^2 at
    frame 0, 2.06 in the second half) never falls below half its open-loop level: the
    loop did not close. The first half's map differs from the second half's, so a
    window from frame 0 gives other numbers.
    """
    v = np.empty((n, 9))
    v[:, :] = -np.log(0.02)
    v[n // 2:, :] = -np.log(SR_EDGE)
    v[:, 4] = -np.log(SR_CENTRE)
    return v


def test_a_run_that_never_rose_averages_its_second_half_everywhere():
    v = _never_rose()
    r = _result(v)
    assert r.loop_status.startswith("did not close: the SR peak (0.9 in the second half) "
                                    "never rose clearly")
    assert r.closure_index == 0 and r.averaging_start == N // 2
    second = np.exp(-v[N // 2:])
    # the map, its corrected field and the summary: one window, the second half
    np.testing.assert_allclose(r.strehl_map(), second.mean(axis=0).reshape(3, 3), rtol=1e-15)
    assert r.corrected_fov_diameter(0.3, refine=256) == pytest.approx(_diameter(SR_EDGE),
                                                                      rel=2e-3)
    s = r.summary()
    assert s["strehl_peak_mean"] == pytest.approx(SR_CENTRE, rel=1e-15)
    assert s["strehl_field_mean"] == pytest.approx((SR_CENTRE + 8 * SR_EDGE) / 9, rel=1e-15)
    assert s["corrected_fov_diameter_arcmin"] == r.corrected_fov_diameter(0.3)
    assert s["averaged_from_s"] == r.times[N // 2] == pytest.approx((N // 2 + 1) * T)
    assert math.isnan(s["closure_time_s"]) and not s["closed"]
    # from frame 0 (the detected "closure", what the map used before) the open-loop
    # first half (edges 0.02) drags the edges to 0.06: another field, 6 % narrower
    assert r.corrected_fov_diameter(0.3, refine=256, start=0) == pytest.approx(
        _diameter(0.06), rel=2e-3)
    assert _diameter(0.06) < 0.95 * _diameter(SR_EDGE)


def test_the_spectrum_of_a_run_that_did_not_close_is_its_second_halfs():
    flat = 0.2 + 0.01 * np.sin(2 * np.pi * 0.23 * np.arange(N))  # never rose
    r = _result(flat)
    assert r.loop_status.startswith("did not close") and r.closure_index == 0
    freqs, psd = r.strehl_peak_spectrum()
    x = np.exp(-flat[N // 2:])
    ref_f, ref_p = signal.welch(x - x.mean(), fs=1.0 / T, nperseg=N // 2)
    np.testing.assert_array_equal(freqs, ref_f)  # 50 samples: 26 frequencies, not 51
    np.testing.assert_allclose(psd, ref_p, rtol=1e-12)


@pytest.mark.parametrize("case", ["closed", "no steady state", "diverged", "open loop"])
def test_the_window_of_each_status(case):
    if case == "closed":  # the step at frame 20: the closure, as before
        v, start = _step(n=N), 20
        r = _result(v)
        assert r.loop_status == "closed" and r.closure_index == 20
    elif case == "no steady state":  # the step at 70: the search's fallback is mid-run
        v, start = _step(n=N, k0=70), N // 2
        r = _result(v)
        assert r.loop_status.startswith("did not close: the SR peak reaches no steady")
    elif case == "diverged":  # closes at frame 1, then grows: the second half, not frame 1
        v, start = np.concatenate([[2.0], np.full(20, 0.1), np.full(N - 21, 0.9)]), N // 2
        r = _result(v)
        assert r.loop_status.startswith("diverged") and r.closure_index == 1
    else:  # open loop: the whole run
        v, start = _step(n=N), 0
        r = _result(v, _config(closed=False))
        assert r.loop_status == "open loop"
    assert r.averaging_start == start
    sr = np.exp(-(v[:, None] * np.ones((1, 9))))[start:]
    np.testing.assert_allclose(r.strehl_map(), sr.mean(axis=0).reshape(3, 3), rtol=1e-14)
    s = r.summary()
    assert s["strehl_peak_mean"] == pytest.approx(sr.max(axis=1).mean(), rel=1e-14)
    assert s["strehl_field_mean"] == pytest.approx(sr.mean(), rel=1e-14)
    assert s["averaged_from_s"] == pytest.approx((start + 1) * T, rel=1e-12)
    assert r.strehl_peak_spectrum()[0].size == min(N - start, 256) // 2 + 1


def test_the_budget_of_a_loop_that_did_not_close_averages_its_second_half():
    from closedloop import simulate

    cfg = small(gain=1e-3)  # too weak to correct within the run
    n = 12  # twice the 5-ms window and 2 frames: the closure can be searched
    r = simulate(cfg, n * cfg.loop.time_step, seed=0, budget_every=1, progress=False)
    assert r.loop_status.startswith("did not close") and r.closure_index == 0
    np.testing.assert_array_equal(r.budget.frames, np.arange(n // 2, n))
    np.testing.assert_allclose(r.budget.measured, r.residual_variance[n // 2:].mean(axis=0),
                               rtol=1e-12)
