"""numba kernels of the DM-space K-L prior projection (no validation; ``dm_kl`` wraps them).

The influence functions are separable, ``IF_a(x, y) = F[x, ax] F[y, ay]`` on the pixel
grid (``modalinfo.bases.influence``), and the structure function is a function of the
pixel lag only, so for two actuators the pupil leaves whole

    sum_p sum_q IF_a(p) D(p - q) IF_b(q) = sum_lx sum_ly c[ax, bx](lx) c[ay, by](ly) D(lx, ly)

with the 1-D correlations ``c[i, j](l) = sum_p F[p, i] F[p - l, j]`` of the factor's
columns: ``n_across^2`` short vectors (``W`` lags each) instead of one FFT per actuator.
"""

from __future__ import annotations

from modalinfo.common.jit import jit


@jit
def factor_correlations(factor, lo, hi, width, corr, lag0):
    """1-D correlations of the factor's columns, every ordered pair.

    ``corr[i, j, k] = sum_p factor[p, i] factor[p - l, j]`` at lag ``l = lag0[i, j] + k``,
    ``lag0[i, j] = lo[i] - hi[j]`` (the smallest lag with a non-zero term); zero past the
    pair's ``hi[i] - lo[j]``.

    factor : (N, n) float64 IN, the 1-D factor on the pixel grid (pixel, actuator column)
    lo, hi : (n,) int64 IN, first and last pixel of each column's support
    width : int IN, ``W`` (>= the largest ``hi[i] - lo[i] + hi[j] - lo[j] + 1``)
    corr : (n, n, W) float64 OUT ; lag0 : (n, n) int64 OUT
    """
    n = factor.shape[1]
    for i in range(n):
        for j in range(n):
            first = lo[i] - hi[j]
            lag0[i, j] = first
            for k in range(width):
                lag = first + k
                p_lo = max(lo[i], lo[j] + lag)
                p_hi = min(hi[i], hi[j] + lag)
                s = 0.0
                for p in range(p_lo, p_hi + 1):
                    s += factor[p, i] * factor[p - lag, j]
                corr[i, j, k] = s


@jit
def separable_projection(corr, lag0, table, centre, cols, group_rows, row_start, index,
                         work, out):
    """``out[index[a], index[b]] = sum_lx sum_ly c[ax, bx](lx) c[ay, by](ly) D(lx, ly)``.

    For every pair of the actuators given (the ones the pupil leaves whole), both
    ``out[index[a], index[b]]`` and ``out[index[b], index[a]]`` (the same number: the
    pair is summed once). Actuators are grouped by grid row: for a pair of rows the
    table is first contracted along y with the rows' correlation (``work``, every x lag),
    then each pair of actuators in the two rows is one ``W``-term product along x.

    corr : (n, n, W) float64 IN ; lag0 : (n, n) int64 IN (``factor_correlations``)
    table : (2 centre + 1, 2 centre + 1) float64 IN, ``D`` at pixel lag ``(ly, lx)`` at
        ``table[ly + centre, lx + centre]``; ``centre >= N - 1 + W`` so that every lag
        read (the zero-padded ones included) is inside
    centre : int IN
    cols : (m,) int64 IN, grid column of each actuator, grouped by grid row
    group_rows : (r,) int64 IN, grid row of each group
    row_start : (r + 1,) int64 IN, the actuators of group ``g`` are
        ``row_start[g] .. row_start[g + 1] - 1``
    index : (m,) int64 IN, output row/column of each actuator
    work : (2 centre + 1,) float64 SCRATCH ; out : (n_out, n_out) float64 OUT
    """
    n_groups = group_rows.shape[0]
    width = corr.shape[2]
    n_lag = table.shape[1]
    for g in range(n_groups):
        ry = group_rows[g]
        for h in range(g, n_groups):
            sy = group_rows[h]
            first = lag0[ry, sy] + centre
            for lx in range(n_lag):
                work[lx] = 0.0
            for k in range(width):
                c = corr[ry, sy, k]
                if c != 0.0:
                    for lx in range(n_lag):
                        work[lx] += c * table[first + k, lx]
            for a in range(row_start[g], row_start[g + 1]):
                ax = cols[a]
                b_first = a if h == g else row_start[h]
                for b in range(b_first, row_start[h + 1]):
                    bx = cols[b]
                    fx = lag0[ax, bx] + centre
                    s = 0.0
                    for k in range(width):
                        s += corr[ax, bx, k] * work[fx + k]
                    out[index[a], index[b]] = s
                    out[index[b], index[a]] = s
