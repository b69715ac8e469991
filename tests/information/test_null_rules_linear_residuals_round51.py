"""Stop 57, fix51-c item 6 (review33 plant R33-C4): the null rules read linear residuals.

``conditional_mutual_information_test`` builds its surrogates from y's residual on a
piecewise-linear fit in z (``RESIDUAL_KNOTS`` hinges, round 50 PART a), while its null
rules (``rotation_null_rule``, ``stationarity_null_rule``, ``level_null_rule``; the
shuffle's ``shuffle_null_rule``) read x's and y's residuals on the *linear* fit, on which
their thresholds were measured (``resampling.residual_split``'s docstring). review33's
plant ``y_resid = resid`` (the rules fed the hinged residual) escaped: the two residuals
differ only where y follows z non-linearly.

Here y does: z is a persistent AR(1) (coefficient 0.99, n = 500, scaled to unit
variance), x = z^2 + 0.1 e, y = z^2 + 0.1 f (e, f white; seed 45). The linear residuals
keep z^2's persistence (largest lag-1 product 0.88: 31.9 effective pairs, below the
rule's 50) and the rotation rule warns; the hinged residual of y is close to f (product
0.10 with x's: 408 effective pairs), and fed to the rules it gives no warning.

Reference: the residuals on the linear fit computed here (``numpy.linalg.lstsq`` of each
series on [1, z], on the values: ``method="gaussian", copula=False`` sees values), and
the rules' verdict on them: the test must warn with exactly that message, once.
"""

import warnings

import numpy as np

from modalinfo.information import conditional_mutual_information_test
from modalinfo.information.resampling import (
    level_null_rule,
    rotation_null_rule,
    stationarity_null_rule,
)

N = 500
NAME = "conditional_mutual_information_test"


def _series(seed: int):
    rng = np.random.default_rng(seed)
    z = np.empty(N)
    z[0] = rng.standard_normal() / np.sqrt(1 - 0.99**2)
    for t in range(1, N):
        z[t] = 0.99 * z[t - 1] + rng.standard_normal()
    z /= z.std()
    return z**2 + 0.1 * rng.standard_normal(N), z**2 + 0.1 * rng.standard_normal(N), z


def _linear_residual(v, z):
    design = np.column_stack([np.ones(N), z])
    return (v - design @ np.linalg.lstsq(design, v, rcond=None)[0])[:, None]


def test_the_null_rules_read_the_linear_residuals():
    x, y, z = _series(45)
    rx, ry = _linear_residual(x, z), _linear_residual(y, z)
    expected = (rotation_null_rule(rx, ry, NAME) or stationarity_null_rule(rx, ry, NAME)
                or level_null_rule(rx, ry, NAME))
    assert expected is not None and "effective pairs" in expected  # the rotation rule
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        conditional_mutual_information_test(x, y, z, method="gaussian", copula=False,
                                            n_surrogates=19, seed=0)
    said = [str(w.message) for w in caught if type(w.message).__name__ == "RotationNullWarning"]
    assert said == [expected], said
