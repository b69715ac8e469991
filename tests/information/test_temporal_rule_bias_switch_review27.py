"""The temporal-neighbour rule stands aside where the bias rule switched the KSG (review27).

Planted bug of review27 (docs/MUTATION.md, round 27) that the fixes-41-c file let
through: ``temporal_neighbour_why`` counted the columns of x and y only for the bias
rule, so a CMI given a 6-column z (a TE map's or a selection's history) that the KSG
bias rule switches to the Gaussian copula was still judged as a KSG estimate. Reference:
the rule as documented, ``n >= k 2.5^d`` over all d = dim x + dim y + dim z columns
(``3 * 2.5^8 = 4578 > 2000``, ``3 * 2.5^2 = 19 <= 2000``), and the function's docstring
("None ... where the KSG's bias rule switched the estimate to the Gaussian copula").
"""

from __future__ import annotations

import numpy as np

from modalinfo.information.conditional import temporal_neighbour_why


def test_a_value_the_bias_rule_switched_is_not_judged():
    rng = np.random.default_rng(27)
    n = 2000
    assert 3 * 2.5**8 > n >= 3 * 2.5**2  # d = 8 switched, d = 2 would not be
    x, y = rng.standard_normal((n, 1)), rng.standard_normal((n, 1))
    z = rng.standard_normal((n, 6))
    # a "value" far above any KSG estimate: judged, it would read as a huge drop
    assert temporal_neighbour_why("ksg", x, y, z, 5.0, {}) is None
    # the same value with no z is a KSG estimate, and is judged (the rule is live)
    assert temporal_neighbour_why("ksg", x, y, np.empty((n, 0)), 5.0, {}) is not None
