"""numba kernels of the conditional-MI estimators (:mod:`modalinfo.information.conditional`).

Kernels take contiguous arrays and scalars only, write into preallocated outputs
(``# OUT``) and never validate; the wrappers in ``conditional.py`` do.
"""

from __future__ import annotations

import math

import numpy as np

from modalinfo._numba import jit
from modalinfo.information._kernels import bin_of, edge_buckets, quantile_edges


@jit
def _c_log_c(c):
    return c * math.log(c) if c > 0 else 0.0


@jit
def quantile_group_codes(arr, pos, code):
    """Mixed-radix cell code of each row of a group under quantile binning of every column.

    Column j is cut at ``numpy.interp(pos, arange(n), sort(arr[:, j]))`` (k + 1 edges,
    :func:`~modalinfo.information._kernels.quantile_edges`, no sort) and each sample gets
    the bin ``searchsorted(edges[1:-1], v, "right")``; the code is
    ``(...(b_0 k + b_1) k + ...) k + b_(d-1)``, as the numpy path of ``conditional.py``.

    arr : (n, d) float64 IN, finite (d may be 0: all codes 0) ; pos : (k + 1,) float64
    IN = numpy.linspace(0, n - 1, k + 1) ; code : (n,) int64 OUT.
    """
    n, d = arr.shape
    k = pos.shape[0] - 1
    edges = np.empty(k + 1)
    for i in range(n):
        code[i] = 0
    for j in range(d):
        col = arr[:, j].copy()  # contiguous: the passes below vectorise (measured 2x)
        lo = col[0]
        hi = col[0]
        for i in range(n):
            v = col[i]
            lo = min(lo, v)
            hi = max(hi, v)
        quantile_edges(col, lo, hi, pos, edges)
        inner = edges[1:k].copy()
        base, inv, nb = edge_buckets(inner, lo, hi)
        for i in range(n):
            code[i] = code[i] * k + bin_of(col[i], inner, lo, inv, nb, base)


@jit
def cmi_dense_counts(cx, cy, cz, nx, ny, nz, counts, out):
    """Compute ``sum c ln c`` and the occupied cells of the four tables of a CMI.

    Parameters
    ----------
    cx, cy, cz : (n,) int64 IN
        Cell code of each sample in the x, y and z groups (0 <= code < nx, ny, nz).
    nx, ny, nz : int
        Number of cells of each group.
    counts : (nz, nx, ny) int64 scratch
        Joint table (overwritten).
    out : (8,) float64 OUT
        ``S_xyz, S_xz, S_yz, S_z`` (sums of c ln c) then ``K_xyz, K_xz, K_yz, K_z``
        (numbers of occupied cells).
    """
    n = cx.shape[0]
    for a in range(nz):
        for b in range(nx):
            for c in range(ny):
                counts[a, b, c] = 0
    for i in range(n):
        counts[cz[i], cx[i], cy[i]] += 1
    for j in range(8):
        out[j] = 0.0
    yz = np.zeros(ny, dtype=np.int64)
    for a in range(nz):
        z_tot = 0
        for c in range(ny):
            yz[c] = 0
        for b in range(nx):
            xz = 0
            for c in range(ny):
                v = counts[a, b, c]
                if v > 0:
                    out[0] += _c_log_c(float(v))
                    out[4] += 1.0
                    xz += v
                    yz[c] += v
            if xz > 0:
                out[1] += _c_log_c(float(xz))
                out[5] += 1.0
                z_tot += xz
        for c in range(ny):
            if yz[c] > 0:
                out[2] += _c_log_c(float(yz[c]))
                out[6] += 1.0
        if z_tot > 0:
            out[3] += _c_log_c(float(z_tot))
            out[7] += 1.0


@jit
def sorted_runs_c_log_c(codes, out):
    """``sum c ln c`` and the number of runs of a sorted int64 code array.

    Parameters
    ----------
    codes : (n,) int64 IN, sorted ascending
    out : (2,) float64 OUT
        Sum over runs of ``c ln c`` (c the run length), number of runs.
    """
    n = codes.shape[0]
    s = 0.0
    k = 0.0
    run = 1
    for i in range(1, n + 1):
        if i < n and codes[i] == codes[i - 1]:
            run += 1
        else:
            s += _c_log_c(float(run))
            k += 1.0
            run = 1
    out[0] = s
    out[1] = k


@jit
def gaussian_loo_log_density_mean(w, h):
    """Mean over samples of ``ln f_{-i}(w_i)`` for an isotropic Gaussian KDE.

    ``f_{-i}(w) = 1 / (n - 1) sum_{j != i} (2 pi h^2)^(-d/2) exp(-|w - w_j|^2 / (2 h^2))``
    (leave-one-out), exact O(n^2 d) double loop. A sample with no neighbour within
    ~38 h (the exponential underflows) gets the density floor of one neighbour at 5 h.

    Parameters
    ----------
    w : (n, d) float64 IN
        Whitened samples.
    h : float
        Kernel standard deviation (in the units of ``w``).

    Returns
    -------
    float
        ``(1/n) sum_i ln f_{-i}(w_i)``.
    """
    n, d = w.shape
    inv2h2 = 0.5 / (h * h)
    log_norm = -0.5 * d * math.log(2.0 * math.pi * h * h) - math.log(n - 1.0)
    floor = math.exp(-12.5)
    acc = np.zeros(n)
    for i in range(n):
        for j in range(i + 1, n):
            r2 = 0.0
            for k in range(d):
                t = w[i, k] - w[j, k]
                r2 += t * t
            e = math.exp(-r2 * inv2h2)
            acc[i] += e
            acc[j] += e
    total = 0.0
    for i in range(n):
        total += math.log(max(acc[i], floor))
    return total / n + log_norm
