"""The raw-value KDE warns of oversmoothing once per FITTED x: a new fit warns again.

References (outside the code under test): the rule the fix of round 16 PART a states
("one oversmoothing warning per fitted estimator", docs/ADVERSARIAL.md) and the
oversmoothing itself - a bimodal x (two normal components 5 sd of the whole apart, each
0.3 wide) under a bandwidth that follows the overall spread is oversmoothed (Silverman
1986, sec. 3.4.4; Scott's factor n^(-1/6) of the overall sd is ~ 1.3 here, four times a
component's width). A second ``fit`` on another such x is another estimate the user
must be told about; a planted bug that kept the flag across fits (R16-A6) silenced it
and escaped every test before this file.
"""

import warnings

import numpy as np

from modalinfo.information import BiasRuleWarning
from modalinfo.information.kde import KDEEngine


def _bimodal(rng, n):
    return np.where(rng.random(n) < 0.5, -5.0, 5.0) + 0.3 * rng.standard_normal(n)


def test_each_fit_warns_once():
    rng = np.random.default_rng(3)
    n = 3000
    engine = KDEEngine(copula=False, bandwidth="scott")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        engine.fit(_bimodal(rng, n))
        engine.score(rng.standard_normal(n))
        engine.score(rng.standard_normal(n))
        first = [w for w in caught if issubclass(w.category, BiasRuleWarning)]
        assert len(first) == 1 and "oversmooths x" in str(first[0].message)
        engine.fit(_bimodal(rng, n))
        engine.score(rng.standard_normal(n))
    bias = [w for w in caught if issubclass(w.category, BiasRuleWarning)]
    assert len(bias) == 2
