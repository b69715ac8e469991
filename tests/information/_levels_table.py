"""The Miller-Madow plug-in CMI of integer columns' table, counted with numpy: one copy.

For the histogram level tests (fix54-c's test_histogram_levels_fix54c, read56's
test_histogram_conditioning_levels_read56). Reference: Miller (1955), each entropy
``-sum p ln p + (cells - 1) / (2 n)`` over the occupied cells that ``numpy.unique``
counts, ``I(x; y | z) = H(x, z) + H(y, z) - H(x, y, z) - H(z)``.
"""

from __future__ import annotations

import numpy as np


def plugin_cmi_mm(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> float:
    """Miller-Madow plug-in I(x; y | z) [nats] of integer columns (n,) each."""
    n = x.size

    def h(*cols: np.ndarray) -> float:
        counts = np.unique(np.stack(cols, axis=1), axis=0, return_counts=True)[1]
        p = counts / n
        return float(-(p * np.log(p)).sum() + (counts.size - 1) / (2.0 * n))

    return h(x, z) + h(y, z) - h(x, y, z) - h(z)
