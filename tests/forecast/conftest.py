"""Data shared by the forecast tests (reference: the AR(1) recursion written out here).

- :func:`ar1`: two independent AR(1) series, ``a[t] = 0.9 a[t-1] + e[t]`` with standard
  normal ``e`` (test_copy_round9, test_copy_audit10).

Test files import the functions (``from .conftest import ar1``).
"""

import numpy as np


def ar1(seed: int, n: int = 600) -> np.ndarray:
    """``(n, 2)`` AR(1) with coefficient 0.9, innovations from ``default_rng(seed)``."""
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n, 2))
    a = np.zeros((n, 2))
    for t in range(1, n):
        a[t] = 0.9 * a[t - 1] + e[t]
    return a
