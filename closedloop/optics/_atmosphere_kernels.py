"""numba kernels of :mod:`closedloop.optics.atmosphere` and :mod:`closedloop.optics.phase_screen`.

Arrays and scalars only; the Python wrappers validate. No random numbers here.
"""

from __future__ import annotations

import numpy as np

from modalinfo.common.jit import jit

__all__ = ["add_separable_terms", "aliased_power", "shift_separable"]


@jit
def add_separable_terms(screen, left, right):
    """Add ``left @ right`` to ``screen`` in place.

    ``screen`` (G, H), ``left`` (G, K), ``right`` (K, H): a sum of K separable
    (outer-product) terms, the real form of the subharmonic Fourier terms. Written out
    so the result does not depend on a BLAS thread count.
    """
    g, h = screen.shape
    k_terms = left.shape[1]
    for r in range(g):
        for k in range(k_terms):
            a = left[r, k]
            for c in range(h):
                screen[r, c] += a * right[k, c]


@jit
def _filter_row(screen, r, col0, wx, segment, wraps, dst):
    """``dst[j] = sum_b wx[b] screen[r, (col0 + j + b) % H]`` (one row, contiguous passes)."""
    h = screen.shape[1]
    n_cols = dst.shape[0]
    tx = wx.shape[0]
    span = n_cols + tx - 1
    if wraps:  # copy the wrapped columns into a contiguous segment
        c = col0
        for j in range(span):
            segment[j] = screen[r, c]
            c += 1
            if c == h:
                c = 0
        row = segment
    else:
        row = screen[r, col0:col0 + span]
    # fused contiguous passes (1-D views let LLVM vectorise); the sums run in tap order,
    # ((w0 a + w1 b) + w2 c) + w3 d, in every branch
    if tx == 4:
        w0, w1, w2, w3 = wx[0], wx[1], wx[2], wx[3]
        for j in range(n_cols):
            dst[j] = w0 * row[j] + w1 * row[j + 1] + w2 * row[j + 2] + w3 * row[j + 3]
    elif tx == 2:
        w0, w1 = wx[0], wx[1]
        for j in range(n_cols):
            dst[j] = w0 * row[j] + w1 * row[j + 1]
    else:
        w = wx[0]
        for j in range(n_cols):
            dst[j] = w * row[j]
        for b in range(1, tx):
            w = wx[b]
            src = row[b:b + n_cols]
            for j in range(n_cols):
                dst[j] += w * src[j]


@jit
def shift_separable(screen, row0, col0, wy, wx, work, out):
    """Resample a periodic screen with a separable filter: the sub-pixel frozen-flow shift.

    ``out[i, j] = sum_a wy[a] (sum_b wx[b] screen[(row0 + i + a) % G, (col0 + j + b) % H])``

    Parameters
    ----------
    screen : (G, H) float64
    row0, col0 : int
        Screen row and column of the first filter tap for output pixel (0, 0),
        already reduced modulo G and H.
    wy, wx : (taps,) float64
        Filter weights along rows and columns (2 for bilinear, 4 for Keys cubic).
    work : (taps, n_cols) float64
        Ring buffer of the last ``taps`` column-filtered rows (stays in L1 cache).
    out : (n_rows, n_cols) float64
        Output, written in place.
    """
    g, h = screen.shape
    n_rows, n_cols = out.shape
    ty = wy.shape[0]
    tx = wx.shape[0]
    wraps = col0 + n_cols + tx - 1 > h
    segment = np.empty(n_cols + tx - 1)
    for a in range(ty - 1):  # the first ty - 1 filtered rows
        _filter_row(screen, (row0 + a) % g, col0, wx, segment, wraps, work[a])
    for i in range(n_rows):
        last = i + ty - 1
        _filter_row(screen, (row0 + last) % g, col0, wx, segment, wraps, work[last % ty])
        dst = out[i]
        if ty == 4:
            s0, s1 = work[i % 4], work[(i + 1) % 4]
            s2, s3 = work[(i + 2) % 4], work[(i + 3) % 4]
            w0, w1, w2, w3 = wy[0], wy[1], wy[2], wy[3]
            for j in range(n_cols):
                dst[j] = w0 * s0[j] + w1 * s1[j] + w2 * s2[j] + w3 * s3[j]
        elif ty == 2:
            s0, s1 = work[i % 2], work[(i + 1) % 2]
            w0, w1 = wy[0], wy[1]
            for j in range(n_cols):
                dst[j] = w0 * s0[j] + w1 * s1[j]
        else:
            src = work[i % ty]
            w = wy[0]
            for j in range(n_cols):
                dst[j] = w * src[j]
            for a in range(1, ty):
                src = work[(i + a) % ty]
                w = wy[a]
                for j in range(n_cols):
                    dst[j] += w * src[j]


@jit
def aliased_power(fq, k, k0sq, orders, out):
    """Add ``sum_{(m, n) != 0, |m|,|n| <= orders} ((fx + m k)^2 + (fy + n k)^2 + k0sq)^(-11/6)``.

    ``fq`` (H,) frequencies [1/m] of the quarter lattice, ``k = 1 / dx``; ``out`` (H, H),
    row index along ``f_y``, column index along ``f_x``; the spectrum's constant and the
    ``r0`` factor are applied by the caller.
    """
    h = fq.shape[0]
    for i in range(h):
        fy = fq[i]
        for j in range(i, h):  # symmetric in (fx, fy): the other triangle is a copy
            fx = fq[j]
            acc = 0.0
            for m in range(-orders, orders + 1):
                ax = fx + m * k
                for n in range(-orders, orders + 1):
                    if m == 0 and n == 0:
                        continue
                    ay = fy + n * k
                    acc += (ax * ax + ay * ay + k0sq) ** (-11.0 / 6.0)
            out[i, j] += acc
            if j != i:
                out[j, i] += acc
