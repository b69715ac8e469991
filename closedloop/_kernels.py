"""numba kernels of the simulator's hot loop (no validation, no random numbers)."""

import numpy as np
from numba import prange

from modalinfo._numba import jit


@jit(parallel=True)
def direction_moments(flat, offsets, sizes, rows, cols, shifts, weights, out_mean, out_var):
    """Mean and variance over the pupil of the summed plane maps, for every direction.

    flat       (sum n_p**2,) float64   IN  plane maps, row-major, concatenated
    offsets    (P,) int64              IN  start of plane p in ``flat``
    sizes      (P,) int64              IN  side of plane p
    rows, cols (n_valid,) int64        IN  pupil pixel indices on the pupil grid
    shifts     (n_dir, P, 2) float64   IN  fractional (col, row) on plane p of pupil pixel (0, 0)
    weights    (P,) float64            IN  factor of each plane (1, or 0 to leave it out)
    out_mean, out_var (n_dir,)         OUT piston and piston-removed variance
    """
    n_dir = shifts.shape[0]
    n_planes = offsets.shape[0]
    n_valid = rows.shape[0]
    for d in prange(n_dir):
        base = np.empty(n_planes, np.int64)
        stride = np.empty(n_planes, np.int64)
        w00 = np.empty(n_planes)
        w01 = np.empty(n_planes)
        w10 = np.empty(n_planes)
        w11 = np.empty(n_planes)
        for p in range(n_planes):
            fc = shifts[d, p, 0]
            fr = shifts[d, p, 1]
            ic = int(np.floor(fc))
            ir = int(np.floor(fr))
            tc = fc - ic
            tr = fr - ir
            stride[p] = sizes[p]
            base[p] = offsets[p] + ir * sizes[p] + ic
            w = weights[p]
            w00[p] = w * (1.0 - tr) * (1.0 - tc)
            w01[p] = w * (1.0 - tr) * tc
            w10[p] = w * tr * (1.0 - tc)
            w11[p] = w * tr * tc
        s = 0.0
        s2 = 0.0
        for k in range(n_valid):
            v = 0.0
            for p in range(n_planes):
                i = base[p] + rows[k] * stride[p] + cols[k]
                n = stride[p]
                v += (w00[p] * flat[i] + w01[p] * flat[i + 1]
                      + w10[p] * flat[i + n] + w11[p] * flat[i + n + 1])
            s += v
            s2 += v * v
        mean = s / n_valid
        out_mean[d] = mean
        out_var[d] = max(s2 / n_valid - mean * mean, 0.0)


@jit
def subtract_scatter(plane_map, index, values, scale):
    """``plane_map.flat[index[k]] -= scale * values[k]`` (IN/OUT plane_map)."""
    flat = plane_map.reshape(-1)
    for k in range(index.shape[0]):
        flat[index[k]] -= scale * values[k]
