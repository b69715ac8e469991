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
- family-wise control: 30 maps of independent AR(1) series (48 cells each) at
  alpha = 0.1. Uncorrected per-cell tests at 0.1 would flag nearly every map
  (1 - 0.9^48 = 0.99); the maximum statistic flags a fraction measured at 0.13-0.14
  over 700 maps (the module notes: slightly above alpha). The count is then
  Binomial(30, 0.14), and >= 9 has probability 0.018; the assertion allows 8, so it
  fails for a control much worse than measured (e.g. p = 0.5: P(<= 8) = 0.008);
- refusals by message (``pytest.raises(match=...)``).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information import TransferEntropyMap, transfer_entropy, transfer_entropy_map
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
                               method="gaussian", units="bits")
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


def test_family_wise_error_of_the_map_under_independence():
    hits = 0
    for seed in range(30):
        rng = np.random.default_rng(100 + seed)
        e = rng.standard_normal((600, 4))
        x = np.zeros_like(e)
        for t in range(1, 600):
            x[t] = 0.7 * x[t - 1] + e[t]
        res = transfer_entropy_map(x[100:], lags=4, alpha=0.1, n_surrogates=49, seed=seed)
        hits += bool(res.significant.any())
    assert hits <= 8


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
