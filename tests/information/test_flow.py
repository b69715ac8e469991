"""Tests of the information-flow map (``modalinfo.information.flow``).

References, all from outside the code under test:

- a planted VAR network (independent AR(1) drivers feeding targets at known lags; no
  chains and no common drivers, so bivariate TE has no indirect link to find): the
  significant pairs are exactly the planted ones, each at its planted lag;
- the frozen-flow geometry of two sensors whose footprints are separated by
  ``b_l`` on layer l moving at ``v_l`` along the separation: the downstream sensor
  sees at t what the upstream one saw at ``t - b_l / v_l`` (Taylor's hypothesis).
  Two layers, written here (a Fourier phase screen per layer with a von Karman-like
  power law, tip/tilt/defocus by least squares on a disc), moving in opposite
  directions: A -> B at lag 6 and B -> A at lag 3 (the synthetic generators of
  ``modalinfo.telemetry.synthetic`` have no lag structure between modes by design, so
  they cannot serve here);
- every Gaussian cell equals :func:`transfer_entropy` (the determinant formula of
  ``conditional.py``) on the same rows, to float rounding (1e-9: two algebraically
  equal forms of a log of ratios of O(1) determinants);
- every Gaussian surrogate cell equals :func:`conditional_mutual_information`
  (method "gaussian", the determinant formula) of the target, the circularly
  shifted lagged source and the target's history (the surrogate's definition), to
  float rounding;
- family-wise control, against the binomial law of an exact test: with N
  surrogates the chance that an exact test rejects at alpha is
  ``floor(alpha (N + 1)) / (N + 1)``, so over M independent maps of independent
  AR(1) series the number of maps with any significant cell is Binomial(M, that).
  Default tier: 100 maps of 48 cells at alpha = 0.1 (49 surrogates, level 0.1): the
  count must lie in [3, 17] (probability 0.98 under the binomial; uncorrected
  per-cell tests would flag 99 % of the maps, and a control as poor as 0.2 fails
  with probability 0.8). Slow tier: 1 500 maps per size (2, 12, 48, 100 cells) at
  alpha = 0.05 and 0.1, each rate within 3.3 binomial standard errors of the exact
  level (the map before the lattice shifts measured 0.057 at level 0.04 on 48 cells,
  3.3 standard errors of 1 500 maps above);
- the step-down maxT p-values against Westfall & Young's Algorithm 4.1 written out
  in the test (a loop over the ordered hypotheses), and the single-step ones against
  the count over the map maximum; step-down <= single-step on a map;
- the lattice of shifts: every pair of {0} and the shifts at least the spacing apart
  on the circle (checked by brute force), none near n / 2;
- end-point matching: with surrogates the map of a log is the map (``match_ends=False``)
  of its frames ``rows``, bit for bit, and those are the window of
  ``resampling.matched_window`` (tested against analytic windows in
  ``test_resampling.py``);
- refusals by message (``pytest.raises(match=...)``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from modalinfo.information import (
    TransferEntropyMap,
    conditional_mutual_information,
    transfer_entropy,
    transfer_entropy_map,
)
from modalinfo.information import flow as flow_mod
from modalinfo.telemetry import ModalLog


def _planted_network(n: int, seed: int) -> np.ndarray:
    """m0, m2, m4 independent AR(1) drivers; m1 <- m0 (lag 2) + m4 (lag 1); m3 <- m2 (lag 4)."""
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n + 100, 6))
    x = np.zeros_like(e)
    for t in range(5, n + 100):
        for j in (0, 2, 4):
            x[t, j] = 0.3 * x[t - 1, j] + e[t, j]
        x[t, 5] = 0.5 * x[t - 1, 5] + e[t, 5]
        x[t, 1] = 0.5 * x[t - 1, 1] + 0.4 * x[t - 2, 0] + 0.4 * x[t - 1, 4] + e[t, 1]
        x[t, 3] = 0.5 * x[t - 1, 3] + 0.4 * x[t - 4, 2] + e[t, 3]
    return x[100:]


PLANTED = {("m0", "m1"): 2, ("m4", "m1"): 1, ("m2", "m3"): 4}


def test_planted_var_network_is_recovered_with_its_lags():
    res = transfer_entropy_map(_planted_network(3000, 0), lags=6, alpha=0.01, seed=0)
    assert isinstance(res, TransferEntropyMap)
    found = {(s, t): lag for s, t, lag, _, _ in res.links()}
    assert found == PLANTED
    assert all(p == pytest.approx(1 / 200) for *_, p in res.links())
    # the diagonal is not a transfer
    assert np.isnan(res.te[np.eye(6, dtype=bool)]).all() and (res.best_lag.diagonal() == -1).all()
    assert "m2             m3                4" in res.table()


def test_histogram_map_finds_the_planted_links():
    X = _planted_network(1500, 1)
    res = transfer_entropy_map(X[:, :4], lags=[2, 4], method="histogram", n_surrogates=19,
                               alpha=0.05, seed=0)
    found = {(s, t): lag for s, t, lag, _, _ in res.links()}
    assert found == {("m0", "m1"): 2, ("m2", "m3"): 4}


def test_gaussian_cells_equal_transfer_entropy_on_the_same_rows():
    X = _planted_network(800, 2)
    res = transfer_entropy_map(X, lags=[1, 3, 5], history=2, n_surrogates=0, units="bits")
    t0 = 5
    for j, i, a in [(0, 1, 0), (2, 3, 2), (5, 0, 1), (4, 1, 0)]:
        lag = int(res.lags[a])
        start = t0 - max(lag, 2)  # transfer_entropy starts at max(lag, history)
        ref = transfer_entropy(X[start:, j], X[start:, i], lag=lag, history=2,
                               method="gaussian", units="bits", copula=False)
        assert res.te[j, i, a] == pytest.approx(ref, rel=1e-9, abs=1e-12)
    assert (res.pvalue[~np.isnan(res.pvalue)] == 1.0).all()  # no surrogate: p = 1


# ----------------------------------------------------------------------------- frozen flow
def _screen(ny: int, nx: int, rng: np.random.Generator) -> np.ndarray:
    fy = np.fft.fftfreq(ny)[:, None]
    fx = np.fft.fftfreq(nx)[None, :]
    psd = (fx**2 + fy**2 + (1 / 8) ** 2) ** (-11 / 6)  # von Karman-like, L0 = 8 px
    w = rng.standard_normal((ny, nx)) + 1j * rng.standard_normal((ny, nx))
    s = np.fft.ifft2(w * np.sqrt(psd)).real
    return s / s.std()


def _two_layer_two_sensor_log(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """Tip, tilt, defocus of sensors A and B (T, 3) each, two frozen-flow layers.

    8-px pupils whose footprints are 12 px apart on both layers (no overlap).
    Layer 1 moves +x at 2 px/frame: B(t) = A(t - 6) on it.
    Layer 2 moves -x at 4 px/frame: A(t) = B(t - 3) on it.
    """
    rng = np.random.default_rng(seed)
    p = 8
    yy, xx = np.mgrid[:p, :p] - (p - 1) / 2
    x, y = xx / (p / 2), yy / (p / 2)
    disc = x**2 + y**2 <= 1
    modes = np.column_stack([np.ones(disc.sum()), 2 * x[disc], 2 * y[disc],
                             np.sqrt(3) * (2 * (x[disc] ** 2 + y[disc] ** 2) - 1)])
    proj = np.linalg.pinv(modes)[1:]  # (3, n_disc): tip, tilt, defocus
    layers = []  # (screen, velocity [px/frame], separation of B from A [px])
    for v, b in ((2, 12), (-4, 12)):
        layers.append((_screen(p, abs(v) * n + 64, rng), v, b))
    cols = np.arange(p)
    out = np.zeros((2, n, 3))
    for t in range(n):
        for k in (0, 1):
            phase = np.zeros((p, p))
            for scr, v, b in layers:
                # content moves at v: position x shows screen column x - v t
                phase += scr[:, (32 + k * b - v * t + cols) % scr.shape[1]]
            out[k, t] = proj @ phase[disc]
    out += 0.05 * out.std(axis=1, keepdims=True) * rng.standard_normal(out.shape)
    return out[0], out[1]


@pytest.mark.parametrize("seed", [0, 1])
def test_frozen_flow_two_layers_show_lagged_transfer_along_each_wind(seed):
    a, b = _two_layer_two_sensor_log(3000, seed)
    log_a = ModalLog(a, rate=1000.0)
    log_b = ModalLog(b, rate=1000.0)
    res = transfer_entropy_map(log_a, extra=log_b, lags=8, history=2, n_surrogates=99,
                               seed=0)
    assert res.labels == ("Z2", "Z3", "Z4", "extra:Z2", "extra:Z3", "extra:Z4")
    assert res.group.tolist() == [0, 0, 0, 1, 1, 1]
    # the strongest transfer of each direction between the sensors is at the layer's lag
    ab = res.te[:3, 3:]
    ba = res.te[3:, :3]
    assert res.lags[np.unravel_index(np.argmax(ab), ab.shape)[2]] == 6
    assert res.lags[np.unravel_index(np.argmax(ba), ba.shape)[2]] == 3
    for m in (0, 2):  # tip (along the wind) and defocus: the upstream copy of each layer
        assert res.best_lag[m, 3 + m] == 6 and res.significant[m, 3 + m, 5]
    for m in range(3):
        assert res.best_lag[3 + m, m] == 3 and res.significant[3 + m, m, 2]


def _independent_ar1(rng: np.random.Generator, n: int, s: int) -> np.ndarray:
    e = rng.standard_normal((n + 100, s))
    x = np.zeros_like(e)
    for t in range(1, n + 100):
        x[t] = 0.7 * x[t - 1] + e[t]
    return x[100:]


def _maps_with_a_link(n_maps: int, n_series: int, n_lags: int, alphas, seed: int):
    rng = np.random.default_rng(seed)
    pmin = np.array([
        np.nanmin(transfer_entropy_map(_independent_ar1(rng, 500, n_series), lags=n_lags,
                                       n_surrogates=49, seed=m).pvalue)
        for m in range(n_maps)])
    return [int(np.count_nonzero(pmin <= a + 1e-12)) for a in alphas]


def _exact_level(alpha: float, n_surrogates: int) -> float:
    return math.floor(alpha * (n_surrogates + 1) + 1e-9) / (n_surrogates + 1)


def test_family_wise_error_of_the_map_under_independence():
    (hits,) = _maps_with_a_link(100, 4, 4, [0.1], seed=100)
    assert _exact_level(0.1, 49) == pytest.approx(0.1)
    assert 3 <= hits <= 17


@pytest.mark.slow
@pytest.mark.parametrize("n_series, n_lags", [(2, 1), (3, 2), (4, 4), (5, 5)])
def test_family_wise_error_within_monte_carlo_error(n_series, n_lags):
    n_maps = 1500
    alphas = (0.05, 0.1)
    hits = _maps_with_a_link(n_maps, n_series, n_lags, alphas, seed=200 + n_series)
    for a, h in zip(alphas, hits, strict=True):
        level = _exact_level(a, 49)
        se = math.sqrt(level * (1 - level) / n_maps)
        assert abs(h / n_maps - level) <= 3.3 * se, (a, h / n_maps, level)


def _westfall_young_step_down(stat, null):
    """Algorithm 4.1 of Westfall & Young (1993), written out."""
    n_surr, k = null.shape
    order = sorted(range(k), key=lambda c: -stat[c])
    adjusted = {}
    running = 0.0
    for rank, c in enumerate(order):
        rest = order[rank:]
        count = sum(1 for s in range(n_surr) if max(null[s, r] for r in rest) >= stat[c])
        running = max(running, (1 + count) / (1 + n_surr))
        adjusted[c] = running
    return np.array([adjusted[c] for c in range(k)])


def test_maxt_pvalues_follow_westfall_young():
    rng = np.random.default_rng(4)
    null = rng.gamma(0.5, size=(39, 12))
    stat = np.concatenate([rng.gamma(0.5, size=9), [6.0, 3.5, 2.5]])
    stat[3] = null[5, 7]  # a tie with a surrogate value counts as exceeded
    got = flow_mod.maxt_pvalues(stat, null)
    np.testing.assert_array_equal(got, _westfall_young_step_down(stat, null))
    single = flow_mod.maxt_pvalues(stat, null, step_down=False)
    ref = np.array([(1 + np.count_nonzero(null.max(axis=1) >= t)) / 40 for t in stat])
    np.testing.assert_array_equal(single, ref)
    assert (got <= single).all() and got[np.argmax(stat)] == single[np.argmax(stat)]


@pytest.mark.parametrize("block", [39, 5 * 39, 1 << 22])
def test_maxt_pvalues_in_column_blocks(monkeypatch, block):
    # the comparison in blocks of 1, 5 and all 12 columns: the same brute-force values
    rng = np.random.default_rng(5)
    null = rng.gamma(0.5, size=(39, 12))
    stat = rng.gamma(2.0, size=12)
    before = null.copy()
    monkeypatch.setattr(flow_mod, "_COMPARE_VALUES", block)
    np.testing.assert_array_equal(flow_mod.maxt_pvalues(stat, null),
                                  _westfall_young_step_down(stat, null))
    np.testing.assert_array_equal(null, before)  # the caller's null is not modified


def test_step_down_map_is_never_less_significant_than_single_step():
    X = _planted_network(600, 5)
    kw = dict(lags=4, n_surrogates=49, seed=1)
    sd = transfer_entropy_map(X, **kw)
    ss = transfer_entropy_map(X, adjust="single-step", **kw)
    assert sd.adjust == "step-down" and ss.adjust == "single-step"
    np.testing.assert_array_equal(sd.te, ss.te)
    off = ~np.isnan(sd.pvalue)
    assert (sd.pvalue[off] <= ss.pvalue[off]).all()
    top = np.unravel_index(np.nanargmax(sd.te), sd.te.shape)
    assert sd.pvalue[top] == ss.pvalue[top] == 1 / 50  # the first step is the single step
    assert set(ss.links()) <= set(sd.links())


def test_surrogate_cells_are_the_cmi_of_the_shifted_source():
    X = _planted_network(400, 6)
    lags, history = np.array([1, 3]), 2
    t0, T = 3, X.shape[0]
    shifts = np.array([17, 150, 388])
    te, null = flow_mod._gaussian_map(X, lags, history, t0, shifts)
    for j, i, a in [(0, 1, 0), (2, 3, 1), (5, 0, 1), (1, 0, 0)]:
        x = X[t0:, i]
        z = np.column_stack([X[t0 - k : T - k, i] for k in range(1, history + 1)])
        y = X[t0 - lags[a] : T - lags[a], j]
        assert te[j, i, a] == pytest.approx(
            conditional_mutual_information(x, y, z, method="gaussian", copula=False),
            rel=1e-9, abs=1e-12)
        for k, s in enumerate(shifts):
            ref = conditional_mutual_information(x, np.roll(y, s), z, method="gaussian",
                                                 copula=False)
            assert null[k, j, i, a] == pytest.approx(ref, rel=1e-9, abs=1e-12)
    assert (null[:, np.eye(6, dtype=bool)] == 0).all()


@pytest.mark.parametrize("n, n_surr, max_lag", [(496, 49, 4), (1000, 199, 10), (97, 9, 3)])
def test_surrogate_shifts_lie_on_a_lattice_away_from_the_original(n, n_surr, max_lag):
    shifts, b = flow_mod.surrogate_shifts(n, n_surr, max_lag, seed=0)
    assert shifts.size == n_surr == np.unique(shifts).size
    pts = np.concatenate([[0], shifts])
    gaps = [min((p - q) % n, (q - p) % n) for p in pts for q in pts if p != q]
    assert min(gaps) >= b >= 1
    assert (shifts % b == 0).all()
    assert all(min((2 * s) % n, n - (2 * s) % n) >= 2 * (b + max_lag) for s in shifts)
    with pytest.raises(ValueError, match="`n_surrogates`=60 circular shifts spaced "
                                         "`min_shift`=9 apart do not fit in 496 rows"):
        flow_mod.surrogate_shifts(496, 60, 4, spacing=9)
    with pytest.raises(ValueError, match="do not fit in 496 rows"):
        transfer_entropy_map(np.random.default_rng(0).standard_normal((500, 2)), lags=4,
                             n_surrogates=499)


def test_refusals_name_the_argument():
    X = _planted_network(300, 3)
    with pytest.raises(ValueError, match="`lags` must be distinct ints >= 0"):
        transfer_entropy_map(X, lags=[1, 1])
    with pytest.raises(ValueError, match="`lags` must be an int >= 1"):
        transfer_entropy_map(X, lags=[0.5])
    with pytest.raises(ValueError, match="`modes` holds 'Z9', not a label"):
        transfer_entropy_map(X, modes=["m0", "Z9"])
    with pytest.raises(TypeError, match="`modes` must be a sequence"):
        transfer_entropy_map(X, modes="m0")
    with pytest.raises(ValueError, match="`extra_modes` selects columns of `extra`"):
        transfer_entropy_map(X, extra_modes=[0])
    with pytest.raises(ValueError, match="`extra` must have 300 frames"):
        transfer_entropy_map(X, extra=X[:200])
    with pytest.raises(ValueError, match="at least 2 series"):
        transfer_entropy_map(X, modes=[0])
    with pytest.raises(ValueError, match="needs at least 320 frames"):
        transfer_entropy_map(X, lags=300)
    with pytest.raises(ValueError, match="would take about .* more than `max_seconds`=0.001"):
        transfer_entropy_map(X, max_seconds=1e-3)
    with pytest.raises(ValueError, match="would take about .* method 'histogram'"):
        transfer_entropy_map(X, method="histogram", max_seconds=1e-3)


def test_refuses_a_map_larger_than_the_available_memory(monkeypatch):
    monkeypatch.setattr(flow_mod, "free_memory_bytes", lambda: 1000.0)
    with pytest.raises(ValueError, match=r"needs about \d+ MiB .* is available"):
        transfer_entropy_map(_planted_network(300, 4))


def test_map_with_surrogates_is_the_map_of_its_matched_rows():
    # two independent AR(1) series of 0.99 over 600 frames (correlation time ~ n / 6):
    # the rotations need the matched window; the result names it and is, bit for bit,
    # the unmatched map of those frames
    from modalinfo.information.resampling import matched_window

    rng = np.random.default_rng(3)
    e = rng.standard_normal((600, 2))
    x = np.zeros_like(e)
    for t in range(1, 600):
        x[t] = 0.99 * x[t - 1] + e[t]
    res = transfer_entropy_map(x, lags=2, n_surrogates=19, seed=4)
    a, b = res.rows
    assert (a, b) == matched_window(x) and 480 <= b - a < 600
    ref = transfer_entropy_map(x[a:b], lags=2, n_surrogates=19, seed=4, match_ends=False)
    assert ref.rows == (0, b - a) and res.n_samples == ref.n_samples == b - a - 2
    np.testing.assert_array_equal(res.te, ref.te)
    np.testing.assert_array_equal(res.pvalue, ref.pvalue)
    # no surrogates, no test: every frame
    assert transfer_entropy_map(x, lags=2, n_surrogates=0).rows == (0, 600)
    # matching never refuses a map that fits in all the frames: 30 shifts with lags
    # up to 20 fit in the 130 rows of 150 frames, not in the window's 100 (all kept)
    a, b = matched_window(x[:150])
    assert b - a == 120
    short = transfer_entropy_map(x[:150], lags=[20], n_surrogates=30, seed=4)
    assert short.rows == (0, 150) and short.n_samples == 130
    with pytest.raises(TypeError, match=r"`match_ends` must be a bool; got str"):
        transfer_entropy_map(x, lags=2, match_ends="yes")


def test_too_few_surrogates_to_reach_alpha_are_refused_zero_is_the_te_alone():
    # adversarial round 6 (a33): 5 surrogates (smallest p-value 1/6) reported a strong
    # x -> y link among "0 significant links"; now refused. 0 keeps its documented
    # meaning: the TE alone, every p-value 1.
    rng = np.random.default_rng(6)
    x = rng.standard_normal(600)
    y = np.r_[0.0, 0.7 * x[:-1]] + 0.5 * rng.standard_normal(600)
    with pytest.raises(ValueError, match=r"`n_surrogates`=5 cannot reach `alpha`=0.05"):
        transfer_entropy_map(np.c_[x, y], lags=2, n_surrogates=5)
    with pytest.raises(ValueError, match=r"`n_surrogates`=9 cannot reach `alpha`=0.01"):
        transfer_entropy_map(np.c_[x, y], lags=2, n_surrogates=9, alpha=0.01)
    alone = transfer_entropy_map(np.c_[x, y], lags=2, n_surrogates=0)
    assert np.all(alone.pvalue[~np.isnan(alone.pvalue)] == 1.0)


# ------------------------------------------------------------------ audit 9 (issue 27)
# Reference: an affine relation has infinite Gaussian CMI (rho = 1 in -0.5 ln(1 - rho^2),
# Cover & Thomas 2006, Example 8.5.1): the Gaussian map refuses the cell (it showed
# 16.6-17.1 nats), as transfer_entropy refuses a delayed copy; a discrete (binary)
# copy's TE is finite (its entropy, ln 2) but its Gaussian one is not: refused too.


@pytest.mark.parametrize("kind", ["delayed", "binary", "contemporaneous"])
def test_gaussian_map_refuses_an_infinite_cell(kind):
    from modalinfo.information.api import InfiniteMIError

    rng = np.random.default_rng(3)
    x = rng.standard_normal(1500)
    if kind == "binary":
        x = (x > 0).astype(float)
    lags, cell = ([0], "m[01] at lag 0") if kind == "contemporaneous" else (2, "m0 at lag 1")
    copy = x.copy() if kind == "contemporaneous" else np.r_[0.0, x[:-1]]
    with pytest.raises(InfiniteMIError, match=f"the source {cell}"):
        transfer_entropy_map(np.c_[x, copy], lags=lags, n_surrogates=19)
    with pytest.raises(InfiniteMIError, match=f"the source {cell}"):  # the restricted map
        transfer_entropy_map(np.c_[x, copy, rng.standard_normal(1500)], lags=lags,
                             n_surrogates=19, candidates=~np.eye(3, dtype=bool))


@pytest.mark.parametrize("scale", [1e300, 1e-300])
def test_map_and_selection_are_unchanged_by_extreme_units(scale):
    """TE and the selection's gains are invariant to a column's scale (audit 9: at 1e300
    the map gave NaN, at 1e-300 the map 0 and the selection no input)."""
    from modalinfo.information import select_inputs

    rng = np.random.default_rng(2)
    x = rng.standard_normal(1500)
    data = np.c_[x, np.r_[0.0, 0.8 * x[:-1]] + 0.6 * rng.standard_normal(1500)]
    ref = transfer_entropy_map(data, lags=2, n_surrogates=0).te
    got = transfer_entropy_map(data * [scale, 1.0], lags=2, n_surrogates=0).te
    np.testing.assert_allclose(got, ref, atol=1e-12)
    sel = [select_inputs(d, target=1, max_lag=2, n_surrogates=19, intervals=False, seed=0)
           for d in (data, data * scale)]
    assert [i.label for i in sel[1].inputs] == [i.label for i in sel[0].inputs] == ["m0[t]"]
    assert sel[1].inputs[0].gain == pytest.approx(sel[0].inputs[0].gain, abs=1e-12)
def test_lags_that_are_not_ints_or_lists_are_refused_naming_lags():
    """Audit 9: lags=2.5 or None raised "'float' object is not iterable"; 2**70 tried to
    allocate the range 1..2**70 before the frame-count rule (lags + 20 frames) could
    refuse it."""
    X = _planted_network(100, 3)
    for bad in (2.5, None):
        with pytest.raises(TypeError, match="`lags` must be an int >= 1"):
            transfer_entropy_map(X, lags=bad)
    with pytest.raises(ValueError, match="`data` needs at least 520 frames"):
        transfer_entropy_map(X, lags=500)
    with pytest.raises(ValueError, match="`lags` must be an int <="):
        transfer_entropy_map(X, lags=2**70)
