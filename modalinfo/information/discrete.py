"""Plug-in information of discrete data: the table rule every MI estimator shares.

The MI of two discrete variables is that of their contingency table (Cover & Thomas
2006, eq. 2.28). Where both variables take so few values that their table holds at
least :data:`DISCRETE_MIN_PER_CELL` samples per cell on average (``m_x m_y <= n / 10``),
the kde, ksg and gaussian engines return the Miller-Madow corrected plug-in MI of that
table (Miller 1955) instead of their continuous estimate: tied values share one kernel
centre or neighbour distance of zero, and a normal model of a binary pair is not its
table (the Gaussian MI of a binary symmetric channel with 10 % errors is 0.51 nats,
its table's 0.368: audit 9, row t14). The histogram engine bins such data into that
table already.
"""

from __future__ import annotations

import numpy as np

from modalinfo.information import _kernels as kern

__all__ = ["DISCRETE_MIN_PER_CELL", "discrete_cmi", "discrete_levels", "discrete_mi",
           "discrete_pair_mi", "discrete_x_levels", "mi_from_counts"]


def mi_from_counts(counts: np.ndarray, bias_correction: str = "miller-madow") -> float:
    """MI in nats of a joint count table, plug-in or Miller-Madow corrected.

    Parameters
    ----------
    counts : numpy.ndarray, shape (kx, ky), int64
        Joint histogram.
    bias_correction : {"miller-madow", "none"}
        Correction applied to the plug-in value.

    Returns
    -------
    float
        Mutual information [nats].
    """
    out = np.empty(4)
    kern.plugin_mi_from_counts(np.ascontiguousarray(counts, dtype=np.int64), out)
    mi = out[0]
    if bias_correction == "miller-madow":
        n = float(counts.sum())
        mi -= (out[1] - out[2] - out[3] + 1.0) / (2.0 * n)
    return float(mi)


#: Least mean number of samples per cell of the contingency table of two discrete
#: variables for the discrete plug-in estimate of the kde, ksg and gaussian engines.
DISCRETE_MIN_PER_CELL = 10


def discrete_levels(x: np.ndarray, max_levels: int) -> tuple[np.ndarray, int] | None:
    """Codes (n,) int64 of the distinct values of x and their number, if <= max_levels.

    None when x has more than ``max_levels`` distinct values (or ``max_levels`` < 2).
    Any ``max_levels + 1`` samples with that many distinct values prove it, so a
    continuous sample is rejected after sorting its first ``max_levels + 1`` values.
    """
    if max_levels < 2 or np.unique(x[: max_levels + 1]).size > max_levels:
        return None
    values, codes = np.unique(x, return_inverse=True)
    if values.size > max_levels:
        return None
    return codes.astype(np.int64, copy=False).ravel(), int(values.size)


def discrete_mi(cx: np.ndarray, mx: int, cy: np.ndarray, my: int) -> float:
    """Plug-in MI (nats) of two coded discrete samples, Miller-Madow corrected."""
    counts = np.bincount(cx * my + cy, minlength=mx * my).reshape(mx, my)
    return mi_from_counts(counts, "miller-madow")


def discrete_x_levels(x: np.ndarray) -> tuple[np.ndarray, int] | None:
    """Return :func:`discrete_levels` of a fixed x that may be one side of a discrete pair.

    y needs >= 2 levels and each cell >= :data:`DISCRETE_MIN_PER_CELL` samples, so x
    has at most ``n / 20`` of them.
    """
    return discrete_levels(x, x.shape[0] // (2 * DISCRETE_MIN_PER_CELL))


def discrete_pair_mi(x_levels: tuple[np.ndarray, int] | None, y: np.ndarray) -> float | None:
    """Return the Miller-Madow plug-in MI (nats) of a discrete pair's table, else None.

    ``x_levels`` from :func:`discrete_x_levels` (None: x is not discrete). The pair is
    discrete when y too has so few values that the table holds at least
    :data:`DISCRETE_MIN_PER_CELL` samples per cell (``m_x m_y <= n / 10``): the rule of
    the kde and ksg engines (kde module notes, "Discrete data").
    """
    if x_levels is None:
        return None
    cx, mx = x_levels
    y_levels = discrete_levels(y, y.shape[0] // (DISCRETE_MIN_PER_CELL * mx))
    return None if y_levels is None else discrete_mi(cx, mx, *y_levels)


def discrete_cmi(x, y, z) -> float | None:
    """Miller-Madow plug-in CMI (nats) of all-discrete (x, y, z), else None.

    The rule of the kde and ksg MI engines (kde module notes, "Discrete data") for the joint table:
    every column takes so few values that the table of (x, y, z) holds at least
    :data:`DISCRETE_MIN_PER_CELL` samples per cell on average; the CMI is then
    ``I(x; (y, z)) - I(x; z)`` of that table. Audit 9: the kernel resolves the atoms of
    discrete data and gave 0.958 nats for the transfer entropy of a binary channel
    (exact ln 2 - H(0.1) = 0.368) and 17.6 for a binary delayed copy (exact ln 2).
    """
    n = x.shape[0]
    budget = n // DISCRETE_MIN_PER_CELL
    codes = []
    cells = 1
    for group in (x, y, z):
        code, m = np.zeros(n, dtype=np.int64), 1
        for j in range(group.shape[1]):
            lv = discrete_levels(group[:, j], budget // cells)
            if lv is None:
                return None
            code, m, cells = code * lv[1] + lv[0], m * lv[1], cells * lv[1]
        codes.append((code, m))
    (cx, mx), (cy, my), (cz, mz) = codes
    return discrete_mi(cx, mx, cy * mz + cz, my * mz) - (discrete_mi(cx, mx, cz, mz)
                                                          if mz > 1 else 0.0)
