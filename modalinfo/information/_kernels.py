"""numba kernels of the MI estimators: one-pass binning, counting and grid interpolation.

Preconditions (checked by the wrappers, never here): arrays are C-contiguous float64
or int64, finite, of matching lengths; bin counts are >= 1; ``inv_width > 0``.
Outputs are preallocated by the caller and marked ``# OUT``.
"""

from __future__ import annotations

import numpy as np

from modalinfo._numba import jit


@jit
def uniform_bin_index(x, lo, inv_width, edges, idx):
    """Equal-width bin index of each sample, exactly as numpy.histogram assigns it.

    x : (n,) float64 IN ; edges : (k + 1,) IN = numpy.linspace(lo, hi, k + 1) ;
    idx : (n,) int64 OUT. The index floor((x - lo) * inv_width) is corrected by one
    against the actual edges (numpy's rule: bins [e_j, e_j+1), the last one closed),
    so samples on an edge land where numpy puts them.
    """
    last = edges.shape[0] - 2
    for i in range(x.shape[0]):
        v = x[i]
        k = int((v - lo) * inv_width)
        if k > last:
            k = last
        elif k < 0:
            k = 0
        if v < edges[k] and k > 0:
            k -= 1
        elif k < last and v >= edges[k + 1]:
            k += 1
        idx[i] = k


@jit
def joint_counts_uniform(ix, y, lo, inv_width, edges, counts):
    """Joint histogram of (bin index of x, equal-width bin of y) in one pass over y.

    ix : (n,) int64 IN, x bin indices ; y : (n,) float64 IN ; edges : (ky + 1,) IN y
    edges as in :func:`uniform_bin_index` ; counts : (kx, ky) int64 OUT (zeroed here).
    """
    counts[:, :] = 0
    last = edges.shape[0] - 2
    for i in range(y.shape[0]):
        v = y[i]
        k = int((v - lo) * inv_width)
        if k > last:
            k = last
        elif k < 0:
            k = 0
        if v < edges[k] and k > 0:
            k -= 1
        elif k < last and v >= edges[k + 1]:
            k += 1
        counts[ix[i], k] += 1


@jit
def joint_counts_index(ix, iy, counts):
    """Joint histogram from two precomputed bin-index arrays.

    ix, iy : (n,) int64 IN ; counts : (n_bins_x, n_bins_y) int64 OUT (zeroed here).
    """
    counts[:, :] = 0
    for i in range(ix.shape[0]):
        counts[ix[i], iy[i]] += 1


@jit
def plugin_mi_from_counts(counts, out):
    """Plug-in MI (nats) of a joint count table and its occupied-bin numbers.

    counts : (kx, ky) int64 IN. out : (4,) float64 OUT =
    [sum_ij c_ij/n log(n c_ij / (c_i. c_.j)), K_xy, K_x, K_y] with K the numbers of
    occupied cells / rows / columns.
    """
    kx = counts.shape[0]
    ky = counts.shape[1]
    row = np.zeros(kx)
    col = np.zeros(ky)
    n = 0.0
    for i in range(kx):
        for j in range(ky):
            c = counts[i, j]
            row[i] += c
            col[j] += c
            n += c
    acc = 0.0
    kxy = 0
    for i in range(kx):
        for j in range(ky):
            c = counts[i, j]
            if c > 0:
                kxy += 1
                acc += c * np.log(c * n / (row[i] * col[j]))
    occ_x = 0
    for i in range(kx):
        if row[i] > 0:
            occ_x += 1
    occ_y = 0
    for j in range(ky):
        if col[j] > 0:
            occ_y += 1
    out[0] = acc / n
    out[1] = kxy
    out[2] = occ_x
    out[3] = occ_y


@jit
def linear_bin_1d(u, lo, inv_delta, grid, idx, frac):
    """Linear binning of samples onto a 1-D grid (Wand & Jones 1995, app. D).

    u : (n,) IN ; grid : (G,) float64 OUT (zeroed here, weights sum to n) ;
    idx : (n,) int64 OUT left node ; frac : (n,) float64 OUT weight of the right node.
    Samples must lie in [lo, lo + (G - 1) / inv_delta].
    """
    grid[:] = 0.0
    last = grid.shape[0] - 2
    for i in range(u.shape[0]):
        t = (u[i] - lo) * inv_delta
        k = int(t)
        if k > last:
            k = last
        elif k < 0:
            k = 0
        f = t - k
        idx[i] = k
        frac[i] = f
        grid[k] += 1.0 - f
        grid[k + 1] += f


@jit
def linear_bin_2d(u, v, lo_u, lo_v, inv_delta, grid, iu, fu, iv, fv):
    """Bilinear binning of points onto a 2-D grid with square cells of side 1/inv_delta.

    u, v : (n,) IN ; grid : (Gu, Gv) float64 OUT (zeroed here, weights sum to n) ;
    iu, iv : (n,) int64 OUT lower-left node ; fu, fv : (n,) float64 OUT fractions.
    """
    grid[:, :] = 0.0
    last_u = grid.shape[0] - 2
    last_v = grid.shape[1] - 2
    for i in range(u.shape[0]):
        t = (u[i] - lo_u) * inv_delta
        k = int(t)
        if k > last_u:
            k = last_u
        elif k < 0:
            k = 0
        a = t - k
        s = (v[i] - lo_v) * inv_delta
        m = int(s)
        if m > last_v:
            m = last_v
        elif m < 0:
            m = 0
        b = s - m
        iu[i] = k
        fu[i] = a
        iv[i] = m
        fv[i] = b
        grid[k, m] += (1.0 - a) * (1.0 - b)
        grid[k + 1, m] += a * (1.0 - b)
        grid[k, m + 1] += (1.0 - a) * b
        grid[k + 1, m + 1] += a * b


@jit
def loo_log_density_sum_1d(dens, idx, frac, n, k0, k1, floor):
    """Sum of log leave-one-out densities of the samples, interpolated from a grid.

    dens : (G,) IN = (1/n) sum_j (binned sample j convolved with the kernel), i.e.
    the density on the grid including every sample's own contribution. The own
    contribution of a sample with fraction f, after linear binning, convolution and
    linear interpolation, is exactly ``s(f) = ((1-f)^2 + f^2) k0 + 2 f (1-f) k1``
    (k0, k1: kernel values at 0 and 1 grid step). f_loo = (n dens_i - s) / (n - 1),
    floored at ``floor``. Returns sum_i log f_loo.
    """
    acc = 0.0
    for i in range(idx.shape[0]):
        k = idx[i]
        f = frac[i]
        val = (1.0 - f) * dens[k] + f * dens[k + 1]
        own = ((1.0 - f) * (1.0 - f) + f * f) * k0 + 2.0 * f * (1.0 - f) * k1
        val = (n * val - own) / (n - 1.0)
        if val < floor:
            val = floor
        acc += np.log(val)
    return acc


@jit
def loo_log_density_sum_2d(dens, iu, fu, iv, fv, n, k0, k1, floor):
    """2-D counterpart of :func:`loo_log_density_sum_1d` for a separable kernel.

    dens : (Gu, Gv) IN, bilinear interpolation; the own contribution is the product
    s(fu) s(fv) of the 1-D ones (k0, k1 of the 1-D factor kernel, same step on both
    axes).
    """
    acc = 0.0
    for i in range(iu.shape[0]):
        k = iu[i]
        m = iv[i]
        a = fu[i]
        b = fv[i]
        val = (
            (1.0 - a) * (1.0 - b) * dens[k, m]
            + a * (1.0 - b) * dens[k + 1, m]
            + (1.0 - a) * b * dens[k, m + 1]
            + a * b * dens[k + 1, m + 1]
        )
        own_u = ((1.0 - a) * (1.0 - a) + a * a) * k0 + 2.0 * a * (1.0 - a) * k1
        own_v = ((1.0 - b) * (1.0 - b) + b * b) * k0 + 2.0 * b * (1.0 - b) * k1
        val = (n * val - own_u * own_v) / (n - 1.0)
        if val < floor:
            val = floor
        acc += np.log(val)
    return acc


@jit
def loo_density_1d(dens, idx, frac, n, k0, k1, floor, out):
    """Leave-one-out density of each sample from a 1-D grid (see loo_log_density_sum_1d).

    out : (n,) float64 OUT, floored at ``floor``.
    """
    for i in range(idx.shape[0]):
        k = idx[i]
        f = frac[i]
        val = (1.0 - f) * dens[k] + f * dens[k + 1]
        own = ((1.0 - f) * (1.0 - f) + f * f) * k0 + 2.0 * f * (1.0 - f) * k1
        val = (n * val - own) / (n - 1.0)
        if val < floor:
            val = floor
        out[i] = val


@jit
def loo_log_ratio_sum_2d(dens, iu, fu, iv, fv, n, k0, k1, floor, fx, fy):
    """Sum over samples of log(f_xy_loo / (f_x_loo f_y_loo)): the resubstitution MI x n.

    dens, iu, fu, iv, fv, n, k0, k1, floor as in :func:`loo_log_density_sum_2d`;
    fx, fy : (n,) IN marginal leave-one-out densities (> 0). The ratios are multiplied
    in runs of up to 8 and one logarithm is taken per run; a run is closed early when
    the running product leaves 1e-150 .. 1e150, so it never under- or overflows (each
    ratio is bounded by the density floors).
    """
    acc = 0.0
    prod = 1.0
    count = 0
    for i in range(iu.shape[0]):
        k = iu[i]
        m = iv[i]
        a = fu[i]
        b = fv[i]
        val = (
            (1.0 - a) * (1.0 - b) * dens[k, m]
            + a * (1.0 - b) * dens[k + 1, m]
            + (1.0 - a) * b * dens[k, m + 1]
            + a * b * dens[k + 1, m + 1]
        )
        own_u = ((1.0 - a) * (1.0 - a) + a * a) * k0 + 2.0 * a * (1.0 - a) * k1
        own_v = ((1.0 - b) * (1.0 - b) + b * b) * k0 + 2.0 * b * (1.0 - b) * k1
        val = (n * val - own_u * own_v) / (n - 1.0)
        if val < floor:
            val = floor
        prod *= val / (fx[i] * fy[i])
        count += 1
        if count == 8 or prod > 1e150 or prod < 1e-150:
            acc += np.log(prod)
            prod = 1.0
            count = 0
    return acc + np.log(prod)


@jit
def standardise(x, out):
    """Write (x - mean) / std (population std, ddof = 0) into out; return (mean, std).

    x : (n,) IN ; out : (n,) float64 OUT. Two passes, no BLAS (whose threads spin
    under contention). std must be > 0 (checked by the wrapper).
    """
    n = x.shape[0]
    s = 0.0
    for i in range(n):
        s += x[i]
    mean = s / n
    ss = 0.0
    for i in range(n):
        d = x[i] - mean
        ss += d * d
    std = np.sqrt(ss / n)
    inv = 1.0 / std
    for i in range(n):
        out[i] = (x[i] - mean) * inv
    return mean, std


@jit
def dot(a, b):
    """Return sum_i a_i b_i (a, b : (n,) IN), without BLAS threads."""
    acc = 0.0
    for i in range(a.shape[0]):
        acc += a[i] * b[i]
    return acc


@jit
def centred_dot_and_norm(xu, y):
    """Return (sum_i xu_i (y_i - mean y), sqrt(sum_i (y_i - mean y)^2)).

    xu : (n,) IN centred, unit-norm x ; y : (n,) IN.
    """
    n = y.shape[0]
    s = 0.0
    for i in range(n):
        s += y[i]
    mean = s / n
    acc = 0.0
    ss = 0.0
    for i in range(n):
        d = y[i] - mean
        acc += xu[i] * d
        ss += d * d
    return acc, np.sqrt(ss)


@jit
def whiten_pair(u, v, r, inv_s, out):
    """Write the Cholesky-whitened second coordinate (v - r u) / s into out (n,) OUT."""
    for i in range(u.shape[0]):
        out[i] = (v[i] - r * u[i]) * inv_s


@jit
def pair_moments(u, y):
    """One pass over (u, y): return (mean of y, std of y (ddof 0), corr(u, y)).

    u : (n,) IN standardised (mean 0, std 1) ; y : (n,) IN, not constant. Sums are
    taken of y - y[0] to limit cancellation; corr uses sum u = 0.
    """
    n = y.shape[0]
    y0 = y[0]
    s = 0.0
    ss = 0.0
    su = 0.0
    for i in range(n):
        d = y[i] - y0
        s += d
        ss += d * d
        su += u[i] * d
    m = s / n
    var = ss / n - m * m
    if var < 0.0:
        var = 0.0
    std = np.sqrt(var)
    return y0 + m, std, su / (n * std)


@jit
def standardise_whiten(u, y, mean, inv_std, r, inv_s, v, w):
    """Write v = (y - mean) inv_std and w = (v - r u) inv_s; return their min and max.

    u, y : (n,) IN ; v, w : (n,) float64 OUT. Returns (v_min, v_max, w_min, w_max).
    """
    vmin = np.inf
    vmax = -np.inf
    wmin = np.inf
    wmax = -np.inf
    for i in range(y.shape[0]):
        a = (y[i] - mean) * inv_std
        b = (a - r * u[i]) * inv_s
        v[i] = a
        w[i] = b
        if a < vmin:
            vmin = a
        if a > vmax:
            vmax = a
        if b < wmin:
            wmin = b
        if b > wmax:
            wmax = b
    return vmin, vmax, wmin, wmax


@jit
def bin_pair_and_marginal(u, w, v, lo_u, lo_w, inv_d2, lo_v, inv_d1, grid2, iu, fu, iw, fw,
                          grid1, iv, fv):
    """Bilinear binning of (u, w) on grid2 and linear binning of v on grid1, one pass.

    As :func:`linear_bin_2d` (step 1/inv_d2) and :func:`linear_bin_1d` (step 1/inv_d1);
    all outputs (grids zeroed here, indices, fractions) are OUT.
    """
    grid2[:, :] = 0.0
    grid1[:] = 0.0
    last_u = grid2.shape[0] - 2
    last_w = grid2.shape[1] - 2
    last_v = grid1.shape[0] - 2
    for i in range(u.shape[0]):
        t = (u[i] - lo_u) * inv_d2
        k = int(t)
        if k > last_u:
            k = last_u
        elif k < 0:
            k = 0
        a = t - k
        t = (w[i] - lo_w) * inv_d2
        m = int(t)
        if m > last_w:
            m = last_w
        elif m < 0:
            m = 0
        b = t - m
        iu[i] = k
        fu[i] = a
        iw[i] = m
        fw[i] = b
        grid2[k, m] += (1.0 - a) * (1.0 - b)
        grid2[k + 1, m] += a * (1.0 - b)
        grid2[k, m + 1] += (1.0 - a) * b
        grid2[k + 1, m + 1] += a * b
        t = (v[i] - lo_v) * inv_d1
        j = int(t)
        if j > last_v:
            j = last_v
        elif j < 0:
            j = 0
        c = t - j
        iv[i] = j
        fv[i] = c
        grid1[j] += 1.0 - c
        grid1[j + 1] += c


@jit
def loo_mi_sum(dens2, iu, fu, iw, fw, k0_2, k1_2, floor2, dens1, iv, fv, k0_1, k1_1,
               floor1, f_u, n):
    """Sum of log(f_uw / (f_u f_v)) with LOO joint and v-marginal densities from grids.

    dens2 (Gu, Gw), iu, fu, iw, fw, k0_2, k1_2, floor2: joint grid as in
    :func:`loo_log_density_sum_2d`; dens1 (Gv,), iv, fv, k0_1, k1_1, floor1: v-marginal
    grid as in :func:`loo_density_1d`; f_u : (n,) IN LOO marginal density of u.
    Products of up to 8 ratios per logarithm, as in :func:`loo_log_ratio_sum_2d`.
    """
    acc = 0.0
    prod = 1.0
    count = 0
    for i in range(iu.shape[0]):
        k = iu[i]
        m = iw[i]
        a = fu[i]
        b = fw[i]
        val = (
            (1.0 - a) * (1.0 - b) * dens2[k, m]
            + a * (1.0 - b) * dens2[k + 1, m]
            + (1.0 - a) * b * dens2[k, m + 1]
            + a * b * dens2[k + 1, m + 1]
        )
        own_u = ((1.0 - a) * (1.0 - a) + a * a) * k0_2 + 2.0 * a * (1.0 - a) * k1_2
        own_w = ((1.0 - b) * (1.0 - b) + b * b) * k0_2 + 2.0 * b * (1.0 - b) * k1_2
        val = (n * val - own_u * own_w) / (n - 1.0)
        if val < floor2:
            val = floor2
        j = iv[i]
        c = fv[i]
        fvv = (1.0 - c) * dens1[j] + c * dens1[j + 1]
        own_v = ((1.0 - c) * (1.0 - c) + c * c) * k0_1 + 2.0 * c * (1.0 - c) * k1_1
        fvv = (n * fvv - own_v) / (n - 1.0)
        if fvv < floor1:
            fvv = floor1
        prod *= val / (f_u[i] * fvv)
        count += 1
        if count == 8 or prod > 1e150 or prod < 1e-150:
            acc += np.log(prod)
            prod = 1.0
            count = 0
    return acc + np.log(prod)
