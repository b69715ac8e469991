"""``resampling.residual_split``'s knots at small n, against numpy's least squares (review33).

Mutation round 33 (docs/MUTATION.md): the round-50 file checks the piecewise-linear fit
at n = 4,000 only, where the cap on the knots (each of the 1 + d_z (1 + K) terms with
>= 20 samples, ``K <= n / (20 d_z) - 2``: no knots below 40 samples per column) never
binds. Reference: ``numpy.linalg.lstsq`` on the docstring's design, a constant, z and
its hinges ``max(0, z - q_j)`` at the ``j / (K + 1)`` quantiles (``numpy.quantile``).
"""

import numpy as np
import pytest

from modalinfo.information.resampling import residual_split


@pytest.mark.parametrize(("n", "knots"), [(40, 0), (59, 0), (60, 1), (200, 8), (1000, 15)])
def test_the_fit_is_numpys_on_the_capped_design(n, knots):
    rng = np.random.default_rng(n)
    z = rng.standard_normal(n)
    y = np.sin(3 * z) + 0.1 * rng.standard_normal(n)
    q = np.quantile(z, np.arange(1, knots + 1) / (knots + 1))
    a = np.column_stack([np.ones(n), z] + [np.maximum(z - qj, 0.0) for qj in q])
    fit_ref = a @ np.linalg.lstsq(a, y, rcond=None)[0]
    fit, resid = residual_split(y[:, None], z[:, None], False, 15)
    np.testing.assert_allclose(fit[:, 0], fit_ref, atol=1e-9)
    np.testing.assert_allclose(resid[:, 0], y - fit_ref, atol=1e-9)
