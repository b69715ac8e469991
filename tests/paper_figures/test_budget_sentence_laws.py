"""The report's budget sentence against hand numbers and the Marechal law.

Reference: a hand-made no-prediction budget whose measured residual (0.5 rad^2) is not
the sum of its terms (0.37 rad^2), as in every real run (the terms are estimated
separately, closedloop.budget). The sentence's published definitions, written in its
words: the temporal term "is X of the residual there" (temporal / measured residual:
0.2 / 0.5 = 40.0 %), and removing it "would raise the Marechal SR from exp(-measured)
to at most exp(-(measured - temporal))" (Marechal: SR = exp(-sigma^2); exp(-0.5) =
0.607, exp(-0.3) = 0.741), at the direction of the best no-prediction SR (the map's
maximum, here the second of three directions).
"""

import math
from types import SimpleNamespace

import numpy as np

from paper_figures.closedloop_runs import budget_sentence


def _runs():
    budget = {
        "directions": np.array([[-10.0, 0.0], [0.0, 0.0], [10.0, 0.0]]),
        "fitting": np.array([0.3, 0.1, 0.3]),
        "aliasing": np.array([0.1, 0.05, 0.1]),
        "temporal": np.array([0.4, 0.2, 0.4]),
        "noise": np.array([0.03, 0.02, 0.03]),
        "measured": np.array([1.0, 0.5, 1.0]),
    }
    none = SimpleNamespace(strehl_map=np.array([[0.3, 0.6, 0.3]]))
    return SimpleNamespace(budget=budget, runs={"none": none}, wavelength=630e-9)


def test_the_sentence_uses_the_measured_residual_and_marechal():
    text, nums = budget_sentence(_runs())
    assert nums["direction"] == (0.0, 0.0)
    assert math.isclose(nums["temporal_share"], 0.2 / 0.5, rel_tol=1e-12)
    assert math.isclose(nums["sr_now"], math.exp(-0.5), rel_tol=1e-12)
    assert math.isclose(nums["sr_bound"], math.exp(-0.3), rel_tol=1e-12)
    assert "is 40.0% of the residual there" in text
    assert f"from {math.exp(-0.5):.3f} to at most {math.exp(-0.3):.3f}" in text
    assert "at 630 nm" in text and '(0", 0")' in text
    # field means over the three directions: temporal 1.0 / 3, fitting + aliasing 1.0 / 3
    assert f"field mean {1.0 / 3:.3f} against {(0.4 + 0.15 + 0.4) / 3:.3f}" in text
