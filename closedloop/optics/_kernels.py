"""numba kernels of the simulator's hot loop (no validation, no random numbers)."""

import numpy as np

# numba through jit.py, which checks the NUMBA_* variables (adversarial round 9 PART b, E15)
from modalinfo.common.jit import jit, prange


@jit(inline="always")
def _common_rows(flat, offsets, sizes, span_lo, span_hi, shifts, taps, weights, common, base):
    """Sum the direction-independent planes into ``base`` (both direction kernels' prologue).

    Returns the pupil's pixel count and its first non-empty row.
    """
    n_planes = offsets.shape[0]
    n_rows = span_lo.shape[0]
    n_cols = base.shape[1]
    count = 0
    for r in range(n_rows):
        count += span_hi[r] - span_lo[r]
    tmp0 = np.empty(n_cols + 3)
    for r in range(n_rows):
        lo = span_lo[r]
        m = span_hi[r] - lo
        if m <= 0:
            continue
        row = base[r, lo:lo + m]
        row[:] = 0.0
        for p in range(n_planes):
            if common[p]:
                _add_read_row(flat, offsets[p], sizes[p], shifts[0, p, 0], shifts[0, p, 1],
                              taps[0, p], weights[p], r, lo, row, tmp0)
    first = 0
    while span_hi[first] <= span_lo[first]:
        first += 1
    return count, first


def _direction_moments(flat, offsets, sizes, span_lo, span_hi, shifts, taps, weights,
                       common, base, out_mean, out_var):
    """Mean and variance over the pupil of the summed plane maps, for every direction.

    flat       (sum n_p**2,) float64   IN  plane maps, row-major, concatenated
    offsets    (P,) int64              IN  start of plane p in ``flat``
    sizes      (P,) int64              IN  side of plane p
    span_lo, span_hi (N,) int64        IN  pupil columns [lo, hi) of each pupil-grid row
                                           (lo == hi for an empty row); the pupil is the
                                           union of these spans (convex rows)
    shifts     (n_dir, P, 2) float64   IN  fractional (col, row) on plane p of pupil pixel (0, 0)
    taps       (n_dir, P, 2, 4) float64 IN the read's weights along columns (``[.., 0, :]``)
                                           and rows (``[.., 1, :]``) at offsets -1, 0, 1, 2
                                           from ``floor(shift)``
                                           (:func:`closedloop.optics.science.read_weights`)
    weights    (P,) float64            IN  factor of each plane (1, or 0 to leave it out)
    common     (P,) bool               IN  plane p has the same shift in every direction
                                           (the ground plane); resampled once into ``base``
    base       (N, N) float64          SCRATCH the common planes' sum on the pupil grid
    out_mean, out_var (n_dir,)         OUT piston and piston-removed variance

    Per pixel the value is ``sum_p w_p (4 x 4-tap read of plane p)`` (a copy at a whole
    pixel shift), the common planes'
    sum first, then the others, each group in plane order. Two things make it fast. The
    common planes are read once per call, not once per direction. The moments are
    accumulated per pupil column (``cs[k] += v``), not in two scalar sums: a scalar
    float reduction is a serial dependency chain that LLVM does not vectorise without
    reassociation (fastmath, which would tie the bits to the vector width), while
    per-column sums are element-wise, so they vectorise and the order of additions stays
    fixed (rows in order for each column, then columns in order) whatever the thread
    count. The moments are taken
    about the direction's first pupil pixel, not zero: ``E[x^2] - E[x]^2`` then cancels
    only the piston's distance to that pixel, not the whole piston (an uncorrected piston
    of tens of radians cost ~1e-11 relative on a variance of ~1 rad^2).
    """
    n_dir = shifts.shape[0]
    n_planes = offsets.shape[0]
    n_rows = span_lo.shape[0]
    n_cols = base.shape[1]
    # the direction-independent part, once
    count, first = _common_rows(flat, offsets, sizes, span_lo, span_hi, shifts, taps, weights,
                                common, base)
    # the one direction-dependent plane, if there is just one (table1): fused loop below
    single = -1
    for p in range(n_planes):
        if not common[p]:
            single = p if single == -1 else -2
    for d in prange(n_dir):
        row = np.empty(n_cols)
        tmp = np.empty(n_cols + 3)
        cs = np.zeros(n_cols)
        cs2 = np.zeros(n_cols)
        # moments about the value of the first pupil pixel, computed as below
        lo = span_lo[first]
        v = row[:1]
        v[0] = base[first, lo]
        for p in range(n_planes):
            if not common[p]:
                _add_read_row(flat, offsets[p], sizes[p], shifts[d, p, 0], shifts[d, p, 1],
                              taps[d, p], weights[p], first, lo, v, tmp)
        ref = v[0]
        if single >= 0:
            _moments_one_plane(flat, offsets[single], sizes[single], shifts[d, single, 0],
                               shifts[d, single, 1], taps[d, single], weights[single],
                               span_lo, span_hi, base, ref, cs, cs2, tmp)
        else:
            for r in range(n_rows):
                lo = span_lo[r]
                m = span_hi[r] - lo
                if m <= 0:
                    continue
                v = row[:m]
                v[:] = base[r, lo:lo + m]
                for p in range(n_planes):
                    if not common[p]:
                        _add_read_row(flat, offsets[p], sizes[p], shifts[d, p, 0],
                                      shifts[d, p, 1], taps[d, p], weights[p], r, lo, v, tmp)
                c1 = cs[lo:lo + m]
                c2 = cs2[lo:lo + m]
                for k in range(m):
                    x = v[k] - ref
                    c1[k] += x
                    c2[k] += x * x
        s = 0.0
        s2 = 0.0
        for k in range(n_cols):
            s += cs[k]
            s2 += cs2[k]
        mean = s / count
        out_mean[d] = ref + mean
        out_var[d] = max(s2 / count - mean * mean, 0.0)


@jit(inline="always")
def _combine_rows(flat, i0, n, wy, m, tmp):
    """``tmp[k] = sum_a wy[a] flat[i0 + a n + k]`` for ``k < m + 3`` (the rows' weighted sum)."""
    w0 = wy[0]
    w1 = wy[1]
    w2 = wy[2]
    w3 = wy[3]
    r0 = flat[i0:i0 + m + 3]
    r1 = flat[i0 + n:i0 + n + m + 3]
    r2 = flat[i0 + 2 * n:i0 + 2 * n + m + 3]
    r3 = flat[i0 + 3 * n:i0 + 3 * n + m + 3]
    for k in range(m + 3):
        tmp[k] = ((w0 * r0[k] + w1 * r1[k]) + w2 * r2[k]) + w3 * r3[k]


@jit(inline="always")
def _moments_one_plane(flat, offset, n, fc, fr, taps, w, span_lo, span_hi, base, ref, cs,
                       cs2, tmp):
    """``cs[k] += x``, ``cs2[k] += x * x`` over the pupil, ``x = base + w (read) - ref``.

    One pass per row for a single direction-dependent plane: the same sums, in the same
    order, as building the row with :func:`_add_read_row` and then accumulating.
    """
    ic = int(np.floor(fc))
    ir = int(np.floor(fr))
    whole = fc == ic and fr == ir
    wx0 = w * taps[0, 0]
    wx1 = w * taps[0, 1]
    wx2 = w * taps[0, 2]
    wx3 = w * taps[0, 3]
    for r in range(span_lo.shape[0]):
        lo = span_lo[r]
        m = span_hi[r] - lo
        if m <= 0:
            continue
        g = base[r, lo:lo + m]
        c1 = cs[lo:lo + m]
        c2 = cs2[lo:lo + m]
        if whole:
            i0 = offset + (ir + r) * n + ic + lo
            src = flat[i0:i0 + m]
            for k in range(m):
                x = (g[k] + w * src[k]) - ref
                c1[k] += x
                c2[k] += x * x
            continue
        _combine_rows(flat, offset + (ir + r - 1) * n + ic + lo - 1, n, taps[1], m, tmp)
        for k in range(m):
            x = (g[k] + (((wx0 * tmp[k] + wx1 * tmp[k + 1]) + wx2 * tmp[k + 2])
                         + wx3 * tmp[k + 3])) - ref
            c1[k] += x
            c2[k] += x * x


@jit(inline="always")
def _add_read_row(flat, offset, n, fc, fr, taps, w, r, lo, row, tmp):
    """``row[k] += w * (read of plane (offset, n) at (fc + lo + k, fr + r))``.

    A copy at a whole-pixel shift, else the separable 4 x 4-tap read with ``taps``
    (rows combined first, then columns).
    """
    ic = int(np.floor(fc))
    ir = int(np.floor(fr))
    m = row.shape[0]
    if fc == ic and fr == ir:
        # whole-pixel shift (the ground plane): one read per pixel
        i0 = offset + (ir + r) * n + ic + lo
        src = flat[i0:i0 + m]
        for k in range(m):
            row[k] += w * src[k]
        return
    _combine_rows(flat, offset + (ir + r - 1) * n + ic + lo - 1, n, taps[1], m, tmp)
    wx0 = w * taps[0, 0]
    wx1 = w * taps[0, 1]
    wx2 = w * taps[0, 2]
    wx3 = w * taps[0, 3]
    for k in range(m):
        row[k] += ((wx0 * tmp[k] + wx1 * tmp[k + 1]) + wx2 * tmp[k + 2]) + wx3 * tmp[k + 3]


# one body, two compilations: threads pay off only for many directions (a parallel region
# costs a thread wake-up, milliseconds on a loaded machine, against ~0.35 ms for table1's
# whole serial call)
direction_moments = jit(parallel=True)(_direction_moments)
direction_moments_serial = jit(_direction_moments)


@jit
def subtract_scatter(plane_map, index, values, scale):
    """``plane_map.flat[index[k]] -= scale * values[k]`` (IN/OUT plane_map)."""
    flat = plane_map.reshape(-1)
    for k in range(index.shape[0]):
        flat[index[k]] -= scale * values[k]


@jit
def mirror_synthesis(quad_t, starts, signs, commands, positions, acc, out):
    """DM surface ``B c`` from the mode shapes on one quadrant of a mirror-symmetric disc.

    quad_t     (M, n_q) float64   IN  mode shapes on the quadrant's pixels, modes grouped
                                      by parity class (class g: rows starts[g]:starts[g+1])
    starts     (5,) int64         IN  class boundaries
    signs      (4, 4) float64     IN  signs[k, g]: factor (+-1) of class g on mirror image k
                                      of the quadrant (identity, x-flip, y-flip, both)
    commands   (M,) float64       IN  commands in the order of ``quad_t``'s rows
    positions  (4, n_q) int64     IN  index in ``out`` of mirror image k of quadrant pixel q
    acc        (4, n_q) float64   SCRATCH per-class partial sums
    out        (n_disc,) float64  OUT surface on the disc's pixels

    Each mode is even or odd under x -> -x and under y -> -y, so the four images of a
    quadrant pixel take the four per-class sums with signs: a quarter of the reads and
    multiplies of ``B c``. The sums run over modes in order, element-wise over pixels
    (vectorised, the same bits whatever the thread count).
    """
    n_q = quad_t.shape[1]
    for g in range(4):
        a = acc[g]
        a[:] = 0.0
        for k in range(starts[g], starts[g + 1]):
            ck = commands[k]
            row = quad_t[k]
            for q in range(n_q):
                a[q] += ck * row[q]
    a0 = acc[0]
    a1 = acc[1]
    a2 = acc[2]
    a3 = acc[3]
    for m in range(4):
        s0 = signs[m, 0]
        s1 = signs[m, 1]
        s2 = signs[m, 2]
        s3 = signs[m, 3]
        pos = positions[m]
        for q in range(n_q):
            out[pos[q]] = ((s0 * a0[q] + s1 * a1[q]) + s2 * a2[q]) + s3 * a3[q]


@jit
def csr_matvec(indptr, indices, data, x, out, accumulate):
    """``out = A @ x`` (or ``out += A @ x`` if ``accumulate``) for a CSR matrix ``A``.

    indptr (n + 1,) int64, indices (nnz,) uint32, data (nnz,) float64: ``A`` in CSR form
    (unsigned column indices: numba then skips the negative-index wrap on every read).

    Each row's sum starts at 0 and runs over its entries in stored order, as scipy's
    ``csr_matvec`` does, so the result has the same bits as ``A @ x`` (and as
    ``out += A @ x``). What differs is speed: a row's sum is a chain of dependent
    additions (latency-bound; the rows of the WFS operators hold 200-430 entries), so
    four rows are summed side by side, four independent chains (eight were slower).
    """
    n = out.shape[0]
    i = 0
    while i + 4 <= n:
        a0 = indptr[i]
        a1 = indptr[i + 1]
        a2 = indptr[i + 2]
        a3 = indptr[i + 3]
        a4 = indptr[i + 4]
        m = min(min(a1 - a0, a2 - a1), min(a3 - a2, a4 - a3))
        d0 = data[a0:a0 + m]
        d1 = data[a1:a1 + m]
        d2 = data[a2:a2 + m]
        d3 = data[a3:a3 + m]
        j0 = indices[a0:a0 + m]
        j1 = indices[a1:a1 + m]
        j2 = indices[a2:a2 + m]
        j3 = indices[a3:a3 + m]
        t0 = 0.0
        t1 = 0.0
        t2 = 0.0
        t3 = 0.0
        for k in range(m):
            t0 += d0[k] * x[j0[k]]
            t1 += d1[k] * x[j1[k]]
            t2 += d2[k] * x[j2[k]]
            t3 += d3[k] * x[j3[k]]
        for jj in range(a0 + m, a1):
            t0 += data[jj] * x[indices[jj]]
        for jj in range(a1 + m, a2):
            t1 += data[jj] * x[indices[jj]]
        for jj in range(a2 + m, a3):
            t2 += data[jj] * x[indices[jj]]
        for jj in range(a3 + m, a4):
            t3 += data[jj] * x[indices[jj]]
        if accumulate:
            out[i] += t0
            out[i + 1] += t1
            out[i + 2] += t2
            out[i + 3] += t3
        else:
            out[i] = t0
            out[i + 1] = t1
            out[i + 2] = t2
            out[i + 3] = t3
        i += 4
    for r in range(i, n):
        t = 0.0
        for jj in range(indptr[r], indptr[r + 1]):
            t += data[jj] * x[indices[jj]]
        if accumulate:
            out[r] += t
        else:
            out[r] = t


@jit
def direction_moments_grouped(flat, offsets, sizes, span_lo, span_hi, shifts, taps, weights,
                              common, base, group, group_plane, group_row, group_col,
                              group_spread, group_taps, comb, out_mean, out_var):
    """:func:`_direction_moments` (serial) with the rows' combination shared by directions.

    The arguments up to ``base`` and the outputs are those of :func:`_direction_moments`.
    Directions whose read of a plane has the same whole row ``floor(shift_row)`` and the
    same row weights (a row of the field grid) differ only in their column: the 4-row
    weighted sum of :func:`_combine_rows` is then formed once per pupil row over the
    union of their columns and each direction reads its columns from it. The same
    operations on the same numbers: the same bits as :func:`_direction_moments`.

    group        (n_dir, P) int64   IN  the group of (direction, plane), -1 for a common
                                        plane or a whole-pixel shift (read directly)
    group_plane, group_row, group_col, group_spread (G,) int64 IN the group's plane, whole
                                        row shift, smallest whole column shift, and largest
                                        less smallest whole column shift
    group_taps   (G, 4) float64     IN  the group's row weights
    comb         (G, W) float64     SCRATCH combined rows, W >= n_cols + 3 + the largest
                                        column spread of a group
    """
    n_dir = shifts.shape[0]
    n_planes = offsets.shape[0]
    n_rows = span_lo.shape[0]
    n_cols = base.shape[1]
    n_groups = group_plane.shape[0]
    # the direction-independent part, once
    count, first = _common_rows(flat, offsets, sizes, span_lo, span_hi, shifts, taps, weights,
                                common, base)
    tmp0 = np.empty(n_cols + 3)
    refs = np.empty(n_dir)
    v1 = np.empty(1)
    for d in range(n_dir):
        lo = span_lo[first]
        v1[0] = base[first, lo]
        for p in range(n_planes):
            if not common[p]:
                _add_read_row(flat, offsets[p], sizes[p], shifts[d, p, 0], shifts[d, p, 1],
                              taps[d, p], weights[p], first, lo, v1, tmp0)
        refs[d] = v1[0]
    cs = np.zeros((n_dir, n_cols))
    cs2 = np.zeros((n_dir, n_cols))
    row = np.empty(n_cols)
    for r in range(n_rows):
        lo = span_lo[r]
        m = span_hi[r] - lo
        if m <= 0:
            continue
        for g in range(n_groups):
            p = group_plane[g]
            n = sizes[p]
            c0 = group_col[g]
            _combine_rows(flat, offsets[p] + (group_row[g] + r - 1) * n + c0 + lo - 1, n,
                          group_taps[g], m + group_spread[g], comb[g])
        for d in range(n_dir):
            v = row[:m]
            v[:] = base[r, lo:lo + m]
            for p in range(n_planes):
                if common[p]:
                    continue
                g = group[d, p]
                w = weights[p]
                if g < 0:  # whole-pixel shift: one read per pixel
                    n = sizes[p]
                    i0 = (offsets[p] + (int(np.floor(shifts[d, p, 1])) + r) * n
                          + int(np.floor(shifts[d, p, 0])) + lo)
                    src = flat[i0:i0 + m]
                    for k in range(m):
                        v[k] += w * src[k]
                    continue
                off = int(np.floor(shifts[d, p, 0])) - group_col[g]
                t = comb[g, off:off + m + 3]
                wx0 = w * taps[d, p, 0, 0]
                wx1 = w * taps[d, p, 0, 1]
                wx2 = w * taps[d, p, 0, 2]
                wx3 = w * taps[d, p, 0, 3]
                for k in range(m):
                    v[k] += ((wx0 * t[k] + wx1 * t[k + 1]) + wx2 * t[k + 2]) + wx3 * t[k + 3]
            ref = refs[d]
            c1 = cs[d, lo:lo + m]
            c2 = cs2[d, lo:lo + m]
            for k in range(m):
                x = v[k] - ref
                c1[k] += x
                c2[k] += x * x
    for d in range(n_dir):
        s = 0.0
        s2 = 0.0
        for k in range(n_cols):
            s += cs[d, k]
            s2 += cs2[d, k]
        mean = s / count
        out_mean[d] = refs[d] + mean
        out_var[d] = max(s2 / count - mean * mean, 0.0)
