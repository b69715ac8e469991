"""Data shared by the forecast tests (reference: the AR(1) recursion written out here).

- :func:`ar1`: two independent AR(1) series, ``a[t] = 0.9 a[t-1] + e[t]`` with standard
  normal ``e`` (test_copy_round9, test_copy_audit10).
- :func:`smooth_log`: round 47's smooth open-loop log and :func:`noisy_var`, a weakly
  coupled VAR(1) (the GCV tests: test_multivariate_gcv_fixes48, test_gcv_qr_fix49b).

Test files import the functions (``from .conftest import ar1``).
"""

import numpy as np

from modalinfo.telemetry import synthetic


def ar1(seed: int, n: int = 600) -> np.ndarray:
    """``(n, 2)`` AR(1) with coefficient 0.9, innovations from ``default_rng(seed)``."""
    rng = np.random.default_rng(seed)
    e = rng.standard_normal((n, 2))
    a = np.zeros((n, 2))
    for t in range(1, n):
        a[t] = 0.9 * a[t - 1] + e[t]
    return a


def smooth_log(n_frames: int = 3000, seed: int = 2) -> np.ndarray:
    """bench_var_ridge_48c.py's round-47 log: Z2-Z7, D = 4 m, r0 = 0.1 m, 10 m/s, 1 kHz."""
    log = synthetic.open_loop_log(range(2, 8), n_frames=n_frames, rate=1000.0, diameter=4.0,
                                  layers=[synthetic.Layer(r0=0.1, wind_speed=10.0)],
                                  seed=seed)
    return np.asarray(log.coeffs, float)


def noisy_var(n: int, seed: int) -> np.ndarray:
    """A weakly coupled VAR(1) of 3 modes, few rows per coefficient: a ridge pays."""
    rng = np.random.default_rng(seed)
    A = np.array([[0.3, 0.0, 0.0], [0.2, 0.2, 0.0], [0.0, -0.2, 0.25]])
    x = np.zeros((n, 3))
    e = rng.standard_normal((n, 3))
    for t in range(1, n):
        x[t] = A @ x[t - 1] + e[t]
    return x
