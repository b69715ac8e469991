"""numba kernels of the actuator influence functions (no validation)."""

from __future__ import annotations

from modalinfo.common.jit import jit


@jit
def separable_surface(grid, first, values, rows, cols, work, out):
    """Surface of a separable banded operator at selected pixels.

    ``out[p] = sum_a sum_b F[rows[p], a] grid[a, b] F[cols[p], b]`` where the 1-D factor
    ``F`` is banded: pixel coordinate ``i`` touches actuators ``first[i] .. first[i] + w - 1``
    with weights ``values[i, :w]`` (zero-padded where the band is shorter).

    grid : (n_act, n_act) float64 IN, commands on the actuator grid (row = y, column = x)
    first : (n,) int64 IN ; values : (n, w) float64 IN
    rows, cols : (P,) int64 IN, pixel row (y) and column (x) on the ``n x n`` grid
    work : (n, n_act) float64 SCRATCH ; out : (P,) float64 OUT
    """
    n_act = grid.shape[0]
    n = first.shape[0]
    w = values.shape[1]
    # work[j, a] = sum_b grid[a, b] F[j, b]: one pass along x for every actuator row,
    # stored column-major so that the pass along y reads a contiguous band
    for a in range(n_act):
        for j in range(n):
            s = 0.0
            f0 = first[j]
            for k in range(w):
                s += grid[a, f0 + k] * values[j, k]
            work[j, a] = s
    # then along y, only at the requested pixels
    for p in range(rows.shape[0]):
        i = rows[p]
        j = cols[p]
        f0 = first[i]
        s = 0.0
        for k in range(w):
            s += values[i, k] * work[j, f0 + k]
        out[p] = s
