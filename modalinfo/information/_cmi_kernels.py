"""numba kernels of the conditional-MI estimators (``histogram_cmi``, ``kde_cmi``).

Kernels take contiguous arrays and scalars only, write into preallocated outputs
(``# OUT``) and never validate; the wrappers in ``histogram.py`` and ``kde.py`` do.
"""

from __future__ import annotations

import math

import numpy as np

from modalinfo.common.jit import jit
from modalinfo.information._kernels import (
    bin_of,
    edge_buckets,
    quantile_edges_scratch,
    selection_buckets,
    split_tied_edges,
)


@jit
def _c_log_c(c):
    return c * math.log(c) if c > 0 else 0.0


@jit
def _column_bins(col, pos, edges, start, slot, j, inner, lo_inv, bases):
    """Quantile edges of one column and the bucket table of :func:`bin_of` (row j)."""
    k = pos.shape[0] - 1
    lo = col[0]
    hi = col[0]
    for i in range(col.shape[0]):
        v = col[i]
        lo = min(lo, v)
        hi = max(hi, v)
    quantile_edges_scratch(col, lo, hi, pos, edges, start, slot)
    inner[j, :] = edges[1:k]
    split_tied_edges(inner[j])  # a pile keeps its own bin (_kernels.split_tied_edges)
    base, inv, nb = edge_buckets(inner[j], lo, hi)
    bases[j, :] = base
    lo_inv[j, 0] = lo
    lo_inv[j, 1] = inv


@jit
def quantile_joint_cells(z, x, y, pos, counts, code):
    """Joint cell of every row of (z, x, y) under quantile binning of each column.

    Column c is cut at ``numpy.interp(pos, arange(n), sort(c))`` (k + 1 edges, exact
    order statistics by :func:`~modalinfo.information._kernels.quantile_edges_scratch`,
    no sort), a sample's bin is ``searchsorted(edges[1:-1], v, "right")``
    (:func:`~modalinfo.information._kernels.bin_of`), and the row's cell is the
    mixed-radix code over the columns of z, then x, then y (radix k): the flat index
    of the (nz, nx, ny) table of :func:`cmi_dense_counts`. One pass over the rows after
    the edges; no per-sample array is allocated when counting.

    z, x, y : (n, dz), (n, dx), (n, dy) float64 IN, finite (dz may be 0) ;
    pos : (k + 1,) float64 IN = numpy.linspace(0, n - 1, k + 1) ;
    counts : (nz nx ny,) int64 OUT, the joint table, or empty ;
    code : (n,) int64 OUT, the cell of each row (written only if counts is empty).
    """
    n = x.shape[0]
    k = pos.shape[0] - 1
    dz, dx, dy = z.shape[1], x.shape[1], y.shape[1]
    d = dz + dx + dy
    nbk = 64 * k  # buckets of edge_buckets for k - 1 inner edges
    inner = np.empty((d, k - 1))
    lo_inv = np.empty((d, 2))
    bases = np.empty((d, nbk + 1), dtype=np.int64)
    edges = np.empty(k + 1)
    nsel = selection_buckets(n)
    start = np.empty(nsel + 1, dtype=np.int64)
    slot = np.empty(nsel, dtype=np.int64)
    for j in range(dz):
        _column_bins(z[:, j], pos, edges, start, slot, j, inner, lo_inv, bases)
    for j in range(dx):
        _column_bins(x[:, j], pos, edges, start, slot, dz + j, inner, lo_inv, bases)
    for j in range(dy):
        _column_bins(y[:, j], pos, edges, start, slot, dz + dx + j, inner, lo_inv, bases)
    dense = counts.shape[0] > 0
    if dense:
        counts[:] = 0
    for i in range(n):
        c = 0
        for j in range(dz):
            c = c * k + bin_of(z[i, j], inner[j], lo_inv[j, 0], lo_inv[j, 1], nbk, bases[j])
        for j in range(dx):
            q = dz + j
            c = c * k + bin_of(x[i, j], inner[q], lo_inv[q, 0], lo_inv[q, 1], nbk, bases[q])
        for j in range(dy):
            q = dz + dx + j
            c = c * k + bin_of(y[i, j], inner[q], lo_inv[q, 0], lo_inv[q, 1], nbk, bases[q])
        if dense:
            counts[c] += 1
        else:
            code[i] = c


@jit
def count_cells(code, counts):
    """Histogram of int64 cell codes: counts (m,) int64 OUT (zeroed here)."""
    counts[:] = 0
    for i in range(code.shape[0]):
        counts[code[i]] += 1


@jit
def cmi_dense_counts(counts, out):
    """Compute ``sum c ln c`` and the occupied cells of the four tables of a CMI.

    Parameters
    ----------
    counts : (nz, nx, ny) int64 IN
        Joint table of the cells (z, x, y).
    out : (8,) float64 OUT
        ``S_xyz, S_xz, S_yz, S_z`` (sums of c ln c) then ``K_xyz, K_xz, K_yz, K_z``
        (numbers of occupied cells).
    """
    nz, nx, ny = counts.shape
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
