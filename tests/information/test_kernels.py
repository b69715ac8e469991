"""numba kernels of modalinfo.information against slow numpy references.

References: numpy.histogram / histogram2d / bincount for binning and counting, a
direct numpy formula for the plug-in MI, explicit loops for linear binning and
interpolation, numpy.interp of numpy.sort for the quantile edges (bit for bit) and
numpy.searchsorted for the bin search. Each kernel is also called from inside an njit function.
"""

import numba as nb
import numpy as np
import pytest

from modalinfo.information import _kernels as kern


@pytest.fixture
def rng():
    return np.random.default_rng(123)


def test_uniform_bin_index_matches_numpy_histogram(rng):
    x = rng.standard_normal(5000)
    k = 17
    lo, hi = x.min(), x.max()
    idx = np.empty(x.size, dtype=np.int64)
    kern.uniform_bin_index(x, lo, k / (hi - lo), np.linspace(lo, hi, k + 1), idx)
    ref, _ = np.histogram(x, bins=k, range=(lo, hi))
    np.testing.assert_array_equal(np.bincount(idx, minlength=k), ref)
    assert idx.max() == k - 1  # the maximum goes to the last bin, as in numpy


def test_uniform_binning_of_values_on_edges_matches_numpy():
    # rounded data put many samples exactly on (or one ulp off) computed edges
    x = np.round(np.random.default_rng(3).standard_normal(3000), 1)
    for k in (2, 3, 7, 16, 25):
        edges = np.linspace(x.min(), x.max(), k + 1)
        idx = np.empty(x.size, dtype=np.int64)
        kern.uniform_bin_index(x, x.min(), k / np.ptp(x), edges, idx)
        ref = np.searchsorted(edges, x, side="right") - 1
        ref[ref == k] = k - 1
        np.testing.assert_array_equal(idx, ref)
        np.testing.assert_array_equal(np.bincount(idx, minlength=k), np.histogram(x, k)[0])


def test_joint_counts_match_histogram2d(rng):
    x = rng.standard_normal(3000)
    y = 0.5 * x + rng.standard_normal(3000)
    kx, ky = 9, 13
    ix = np.empty(x.size, dtype=np.int64)
    kern.uniform_bin_index(x, x.min(), kx / np.ptp(x), np.linspace(x.min(), x.max(), kx + 1), ix)
    counts = np.empty((kx, ky), dtype=np.int64)
    ey = np.linspace(y.min(), y.max(), ky + 1)
    kern.joint_counts_uniform(ix, y, y.min(), ky / np.ptp(y), ey, counts)
    ref, _, _ = np.histogram2d(x, y, bins=(kx, ky))
    np.testing.assert_array_equal(counts, ref.astype(np.int64))
    iy = np.empty(y.size, dtype=np.int64)
    kern.uniform_bin_index(y, y.min(), ky / np.ptp(y), ey, iy)
    counts2 = np.full((kx, ky), -5, dtype=np.int64)
    kern.joint_counts_index(ix, iy, counts2)
    np.testing.assert_array_equal(counts2, counts)


def test_plugin_mi_from_counts_matches_numpy_formula(rng):
    counts = rng.integers(0, 20, size=(7, 5)).astype(np.int64)
    counts[2, :] = 0  # an empty row
    out = np.empty(4)
    kern.plugin_mi_from_counts(counts, out)
    p = counts / counts.sum()
    px = p.sum(1, keepdims=True)
    py = p.sum(0, keepdims=True)
    nz = p > 0
    ref = np.sum(p[nz] * np.log(p[nz] / (px @ py)[nz]))
    assert out[0] == pytest.approx(ref, rel=1e-12, abs=1e-15)
    assert out[1:].tolist() == [np.count_nonzero(counts), 6, np.count_nonzero(counts.sum(0))]


def _linear_bin_ref(u, lo, delta, g):
    grid = np.zeros(g)
    for val in u:
        t = (val - lo) / delta
        k = min(int(np.floor(t)), g - 2)
        f = t - k
        grid[k] += 1 - f
        grid[k + 1] += f
    return grid


def _bilinear_bin_ref(u, v, lo_u, lo_v, delta, shape):
    ref = np.zeros(shape)
    for a, b in zip(u, v, strict=True):
        ta, tb = (a - lo_u) / delta, (b - lo_v) / delta
        ka, kb = int(np.floor(ta)), int(np.floor(tb))
        fa, fb = ta - ka, tb - kb
        ref[ka, kb] += (1 - fa) * (1 - fb)
        ref[ka + 1, kb] += fa * (1 - fb)
        ref[ka, kb + 1] += (1 - fa) * fb
        ref[ka + 1, kb + 1] += fa * fb
    return ref


def _cells(x, lo, delta):
    t = (x - lo) / delta
    k = np.floor(t).astype(np.int64)
    return k, t - k


def test_linear_binning_1d_and_2d_against_loops(rng):
    u = rng.standard_normal(500)
    v = rng.standard_normal(500)
    lo, delta, g = -6.0, 0.1, 121
    grid = np.empty(g)
    idx = np.empty(u.size, dtype=np.int32)
    frac = np.empty(u.size)
    kern.linear_bin_1d(u, lo, 1 / delta, grid, idx, frac)
    np.testing.assert_allclose(grid, _linear_bin_ref(u, lo, delta, g), atol=1e-12)
    assert grid.sum() == pytest.approx(u.size)
    k, f = _cells(u, lo, delta)
    np.testing.assert_array_equal(idx, k)
    np.testing.assert_allclose(frac, f, atol=1e-12)
    # The first moment is preserved exactly by linear binning.
    nodes = lo + delta * np.arange(g)
    assert grid @ nodes == pytest.approx(u.sum(), rel=1e-12)

    shape = (g, g - 7)
    grid2 = np.empty(shape)
    cell = np.empty(u.size, dtype=np.int32)
    fu, fv = np.empty(u.size), np.empty(u.size)
    kern.linear_bin_2d(u, v, lo, lo + 0.3, 1 / delta, grid2, cell, fu, fv)
    np.testing.assert_allclose(grid2, _bilinear_bin_ref(u, v, lo, lo + 0.3, delta, shape),
                               atol=1e-12)
    kv, f_v = _cells(v, lo + 0.3, delta)
    np.testing.assert_array_equal(cell, k * shape[1] + kv)  # flat row-major lower-left node
    np.testing.assert_allclose(fu, f, atol=1e-12)
    np.testing.assert_allclose(fv, f_v, atol=1e-12)


def _own_ref(f, k0, k1):
    return ((1 - f) ** 2 + f**2) * k0 + 2 * f * (1 - f) * k1


def _loo_1d_ref(idx, frac, dens, n, k0, k1, floor):
    interp = (1 - frac) * dens[idx] + frac * dens[idx + 1]
    return np.maximum((n * interp - _own_ref(frac, k0, k1)) / (n - 1), floor)


def _loo_2d_ref(iu, fu, iv, fv, dens, n, k0, k1, floor):
    bil = ((1 - fu) * (1 - fv) * dens[iu, iv] + fu * (1 - fv) * dens[iu + 1, iv]
           + (1 - fu) * fv * dens[iu, iv + 1] + fu * fv * dens[iu + 1, iv + 1])
    own = _own_ref(fu, k0, k1) * _own_ref(fv, k0, k1)
    return np.maximum((n * bil - own) / (n - 1), floor)


def test_loo_density_kernels_against_numpy(rng):
    g = 50
    dens = rng.random(g) + 0.5
    idx = rng.integers(0, g - 1, size=200).astype(np.int32)
    frac = rng.random(200)
    n, k0, k1, floor = 200.0, 0.3, 0.2, 1e-3
    ref = _loo_1d_ref(idx, frac, dens, n, k0, k1, floor)
    out = np.empty(200)
    kern.loo_density_1d(dens, idx, frac, n, k0, k1, floor, out)
    np.testing.assert_allclose(out, ref, rtol=1e-13)
    # in place over the fractions, as the KDE wrapper calls it
    frac_copy = frac.copy()
    kern.loo_density_1d(dens, idx, frac_copy, n, k0, k1, floor, frac_copy)
    np.testing.assert_allclose(frac_copy, ref, rtol=1e-13)
    dens2 = rng.random((g, g + 3)) + 0.5
    iu, iv = idx, rng.integers(0, g + 2, size=200).astype(np.int32)
    fu, fv = frac, rng.random(200)
    cell = (iu * (g + 3) + iv).astype(np.int32)
    ref2 = _loo_2d_ref(iu, fu, iv, fv, dens2, n, k0, k1, floor)
    got = kern.loo_log_density_sum_2d(dens2, cell, fu, fv, n, k0, k1, floor)
    assert got == pytest.approx(np.log(ref2).sum(), rel=1e-12)
    fx, fy = rng.random(200) + 0.1, rng.random(200) + 0.1
    got = kern.loo_log_ratio_sum_2d(dens2, cell, fu, fv, n, k0, k1, floor, fx, fy)
    assert got == pytest.approx(np.log(ref2 / (fx * fy)).sum(), rel=1e-10)
    # the floor binds where the grid density is below the own contribution
    kern.loo_density_1d(np.full(g, 1e-9), idx, frac, n, k0, k1, floor, out)
    np.testing.assert_array_equal(out, floor)


def test_fused_score_kernels_against_numpy(rng):
    n = 3000
    u = rng.standard_normal(n)
    u = (u - u.mean()) / u.std()
    y = 2.0 + 0.7 * u + 0.5 * rng.standard_normal(n) ** 3
    mean, std, r = kern.pair_moments(u, y)
    assert mean == pytest.approx(y.mean(), rel=1e-13)
    assert std == pytest.approx(y.std(), rel=1e-12)
    assert r == pytest.approx(np.corrcoef(u, y)[0, 1], rel=1e-12)
    inv_std, inv_s = 1 / std, 1 / np.sqrt(1 - r * r)
    v = (y - mean) * inv_std
    w = (v - r * u) * inv_s
    got = kern.whitened_range(u, y, mean, inv_std, r, inv_s)
    np.testing.assert_allclose(got, [v.min(), v.max(), w.min(), w.max()], rtol=1e-14)
    pad, g2, g1 = 1.0, 90, 300
    lo_u, lo_w, lo_v = u.min() - pad, w.min() - pad, v.min() - pad
    d2 = (max(np.ptp(u), np.ptp(w)) + 2 * pad) / (g2 - 1)
    d1 = (np.ptp(v) + 2 * pad) / (g1 - 1)
    gu = int(np.ceil((np.ptp(u) + 2 * pad) / d2)) + 2
    gw = int(np.ceil((np.ptp(w) + 2 * pad) / d2)) + 2
    grid2, grid1 = np.empty((gu, gw)), np.empty(g1)
    cell, iv = np.empty(n, dtype=np.int32), np.empty(n, dtype=np.int32)
    fu, fw, fv = np.empty(n), np.empty(n), np.empty(n)
    kern.bin_whitened(u, y, mean, inv_std, r, inv_s, lo_u, lo_w, 1 / d2, lo_v, 1 / d1, grid2,
                      cell, fu, fw, grid1, iv, fv)
    np.testing.assert_allclose(grid2, _bilinear_bin_ref(u, w, lo_u, lo_w, d2, (gu, gw)),
                               atol=1e-12)
    np.testing.assert_allclose(grid1, _linear_bin_ref(v, lo_v, d1, g1), atol=1e-12)
    (ku, au), (kw, aw), (kv, av) = _cells(u, lo_u, d2), _cells(w, lo_w, d2), _cells(v, lo_v, d1)
    np.testing.assert_array_equal(cell, ku * gw + kw)
    np.testing.assert_array_equal(iv, kv)
    np.testing.assert_allclose(np.column_stack([fu, fw, fv]), np.column_stack([au, aw, av]),
                               atol=1e-10)
    dens2 = rng.random((gu, gw)) + 0.5
    dens1 = rng.random(g1) + 0.5
    f_u = rng.random(n) + 0.1
    k0_2, k1_2, k0_1, k1_1, floor2, floor1 = 0.3, 0.2, 0.4, 0.35, 1e-3, 2e-3
    f_uw = _loo_2d_ref(ku, au, kw, aw, dens2, n, k0_2, k1_2, floor2)
    f_v = _loo_1d_ref(kv, av, dens1, n, k0_1, k1_1, floor1)
    got = kern.loo_mi_sum(dens2, cell, fu, fw, k0_2, k1_2, floor2, dens1, iv, fv, k0_1, k1_1,
                          floor1, f_u, float(n))
    assert got == pytest.approx(np.log(f_uw / (f_u * f_v)).sum(), rel=1e-10)


def test_kernels_callable_from_njit(rng):
    @nb.njit
    def driver(x, k):
        idx = np.empty(x.shape[0], dtype=np.int64)
        kern.uniform_bin_index(x, x.min(), k / (x.max() - x.min()),
                               np.linspace(x.min(), x.max(), k + 1), idx)
        counts = np.empty((k, k), dtype=np.int64)
        kern.joint_counts_index(idx, idx, counts)
        out = np.empty(4)
        kern.plugin_mi_from_counts(counts, out)
        return out[0]

    x = rng.standard_normal(1000)
    # I(X; X) of the binned variable is its discrete entropy.
    p = np.histogram(x, bins=8)[0] / x.size
    p = p[p > 0]
    assert driver(x, 8) == pytest.approx(-np.sum(p * np.log(p)), rel=1e-12)


def test_moment_kernels_against_numpy(rng):
    x = 3.0 + 2.0 * rng.standard_normal(1001)
    y = rng.standard_normal(1001) - 0.5 * x
    out = np.empty_like(x)
    mean, std = kern.standardise(x, out)
    assert mean == pytest.approx(x.mean(), rel=1e-13)
    assert std == pytest.approx(x.std(), rel=1e-13)
    np.testing.assert_allclose(out, (x - x.mean()) / x.std(), rtol=1e-12, atol=1e-14)
    assert kern.dot(x, y) == pytest.approx(np.dot(x, y), rel=1e-12)
    xu = (x - x.mean()) / np.linalg.norm(x - x.mean())
    num, norm = kern.centred_dot_and_norm(xu, y)
    assert num / norm == pytest.approx(np.corrcoef(x, y)[0, 1], rel=1e-12)
    w = np.empty_like(x)
    kern.whiten_pair(x, y, 0.3, 2.0, w)
    np.testing.assert_allclose(w, (y - 0.3 * x) * 2.0, rtol=1e-14)


def test_log_ratio_sum_survives_extreme_ratios(rng):
    # eight ratios of 1e+100 (then eight of 1e-100) overflow (underflow) a plain product
    g = 10
    dens = np.full((g, g), 1.0)
    m = 16
    cell = np.zeros(m, dtype=np.int32)
    fu = np.zeros(m)
    fx = np.where(np.arange(m) < 8, 1e-100, 1e100)
    fy = np.ones(m)
    n, k0, k1, floor = 1e6, 0.0, 0.0, 1e-300
    got = kern.loo_log_ratio_sum_2d(dens, cell, fu, fu, n, k0, k1, floor, fx, fy)
    want = np.sum(np.log((n * 1.0) / (n - 1) / fx))
    assert got == pytest.approx(want, abs=1e-9)


def _hard_samples(rng, n):
    """Samples that stress a bucket selection: ties, heavy tails, a huge range, sorted."""
    return {
        "normal": rng.standard_normal(n),
        "heavy": rng.standard_cauchy(n) ** 3,
        "discrete": rng.integers(0, 5, n).astype(float),
        "tiny-ties": np.round(rng.standard_normal(n), 1) * 1e-300,
        "huge-range": np.where(rng.random(n) < 0.5, 1e308, -1e308) * rng.random(n),
        "descending": np.sort(rng.standard_normal(n))[::-1].copy(),
        "one-outlier": np.r_[rng.standard_normal(n - 1), 1e12],
    }


@pytest.mark.parametrize("n", [10, 11, 97, 4000])
def test_quantile_edges_equal_numpy_interp_of_the_sorted_sample(rng, n):
    # reference: the definition, numpy.interp over numpy.sort (bit for bit)
    for name, x in _hard_samples(rng, n).items():
        for k in (2, 3, 7, 14, 40):
            pos = np.linspace(0.0, n - 1.0, k + 1)
            ref = np.interp(pos, np.arange(n, dtype=float), np.sort(x))
            out = np.empty(k + 1)
            kern.quantile_edges(x, x.min(), x.max(), pos, out)
            np.testing.assert_array_equal(out, ref, err_msg=f"{name}, k = {k}")


@pytest.mark.parametrize("n", [10, 4000])
def test_sorted_edges_bin_index_equals_searchsorted(rng, n):
    # reference: numpy.searchsorted(inner, x, side="right"), incl. samples on edges
    for name, x in _hard_samples(rng, n).items():
        for k in (2, 5, 14, 40):
            inner = np.sort(rng.choice(x, k - 1))  # edges that are samples: ties on edges
            idx = np.empty(n, dtype=np.int64)
            kern.sorted_edges_bin_index(x, x.min(), x.max(), inner, idx)
            np.testing.assert_array_equal(idx, np.searchsorted(inner, x, side="right"),
                                          err_msg=f"{name}, k = {k}")
