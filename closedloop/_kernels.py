"""numba kernels of the simulator's hot loop (no validation, no random numbers)."""

import numpy as np
from numba import prange

from modalinfo._numba import jit


def _direction_moments(flat, offsets, sizes, span_lo, span_hi, shifts, weights,
                      out_mean, out_var):
    """Mean and variance over the pupil of the summed plane maps, for every direction.

    flat       (sum n_p**2,) float64   IN  plane maps, row-major, concatenated
    offsets    (P,) int64              IN  start of plane p in ``flat``
    sizes      (P,) int64              IN  side of plane p
    span_lo, span_hi (N,) int64        IN  pupil columns [lo, hi) of each pupil-grid row
                                           (lo == hi for an empty row); the pupil is the
                                           union of these spans (convex rows)
    shifts     (n_dir, P, 2) float64   IN  fractional (col, row) on plane p of pupil pixel (0, 0)
    weights    (P,) float64            IN  factor of each plane (1, or 0 to leave it out)
    out_mean, out_var (n_dir,)         OUT piston and piston-removed variance
    """
    n_dir = shifts.shape[0]
    n_planes = offsets.shape[0]
    n_rows = span_lo.shape[0]
    width = 0
    count = 0
    for r in range(n_rows):
        width = max(width, span_hi[r] - span_lo[r])
        count += span_hi[r] - span_lo[r]
    for d in prange(n_dir):
        row = np.empty(width)
        s = 0.0
        s2 = 0.0
        for r in range(n_rows):
            lo = span_lo[r]
            m = span_hi[r] - lo
            if m <= 0:
                continue
            row[:m] = 0.0
            for p in range(n_planes):
                fc = shifts[d, p, 0]
                fr = shifts[d, p, 1]
                ic = int(np.floor(fc))
                ir = int(np.floor(fr))
                tc = fc - ic
                tr = fr - ir
                n = sizes[p]
                w = weights[p]
                a = w * (1.0 - tr) * (1.0 - tc)
                b = w * (1.0 - tr) * tc
                c = w * tr * (1.0 - tc)
                e = w * tr * tc
                i0 = offsets[p] + (ir + r) * n + ic + lo
                i1 = i0 + n
                if tc == 0.0 and tr == 0.0:
                    # whole-pixel shift (the ground plane): one read per pixel
                    for k in range(m):
                        row[k] += w * flat[i0 + k]
                    continue
                for k in range(m):
                    row[k] += (a * flat[i0 + k] + b * flat[i0 + k + 1]
                               + c * flat[i1 + k] + e * flat[i1 + k + 1])
            for k in range(m):
                v = row[k]
                s += v
                s2 += v * v
        mean = s / count
        out_mean[d] = mean
        out_var[d] = max(s2 / count - mean * mean, 0.0)


# one body, two compilations: threads pay off only for many directions (a parallel region
# costs a thread wake-up, milliseconds on a loaded machine)
direction_moments = jit(parallel=True)(_direction_moments)
direction_moments_serial = jit(_direction_moments)


@jit
def subtract_scatter(plane_map, index, values, scale):
    """``plane_map.flat[index[k]] -= scale * values[k]`` (IN/OUT plane_map)."""
    flat = plane_map.reshape(-1)
    for k in range(index.shape[0]):
        flat[index[k]] -= scale * values[k]
