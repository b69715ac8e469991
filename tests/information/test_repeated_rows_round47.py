"""Rows repeated in every column (duplicated frames) and the KSG estimators (round 47 PART a).

A log whose frames repeat (a logger re-sending frames, a pair resampled to twice its
rate) puts each repeated (x, y) row at distance ~0 from its twin; KSG's neighbour counts
read that as dependence. Reference: the exact MI of a Gaussian pair, -0.5 ln(1 - rho^2)
= 0.5108 nats at rho = 0.8; before the fix `mutual_information` returned 1.246 with every
row doubled under a warning calling the value "a lower bound" (S213), 0.574 and 0.728
silently with 10 % and 30 % of rows repeated (D02, D03), the CMI given an independent z
0.687 and `MutualInformation.score` 0.742 silently at 30 % (D12, D13). The kde, histogram
and gaussian estimators stay within 0.05 nats of 0.5108 on the doubled pair, and rounded
data (ties within a column across different rows) keep their value: neither is judged.
"""

import warnings

import numpy as np
import pytest

from modalinfo.information import (
    BiasRuleWarning,
    MutualInformation,
    conditional_mutual_information,
    mutual_information,
)

N = 3000
RHO = 0.8
EXACT = -0.5 * np.log(1 - RHO**2)  # 0.5108 nats


def _pair(seed=5):
    rng = np.random.default_rng(seed)
    x = rng.standard_normal(N)
    y = RHO * x + np.sqrt(1 - RHO**2) * rng.standard_normal(N)
    return rng, x, y


def _repeated(rng, share):
    """Row indices: every row once, plus ``share * N`` rows again (at random places)."""
    idx = np.r_[np.arange(N), rng.choice(N, int(share * N), replace=False)]
    rng.shuffle(idx)
    return idx


def _repeat_warnings(record):
    return [w for w in record if issubclass(w.category, BiasRuleWarning)
            and "repeat an earlier row" in str(w.message)]


def test_every_row_doubled_warns_with_the_count():
    _, x, y = _pair()
    with pytest.warns(BiasRuleWarning, match=r"3000 of the 6000 rows .*duplicated frames") as rec:
        value = mutual_information(np.repeat(x, 2), np.repeat(y, 2), method="ksg")
    assert value > EXACT + 0.5  # the bias the warning names (1.246 for 0.511)
    assert len([w for w in rec if issubclass(w.category, BiasRuleWarning)]) == 1  # one warning


@pytest.mark.parametrize("share", [0.1, 0.3])
def test_a_share_of_rows_repeated_warns(share):
    rng, x, y = _pair()
    idx = _repeated(rng, share)
    with pytest.warns(BiasRuleWarning, match="method='ksg'") as rec:
        mutual_information(x[idx], y[idx], method="ksg")
    assert len(_repeat_warnings(rec)) == 1


def test_cmi_and_the_class_warn_too():
    rng, x, y = _pair()
    z = rng.standard_normal(N)
    idx = _repeated(rng, 0.3)
    with pytest.warns(BiasRuleWarning) as rec:
        conditional_mutual_information(x[idx], y[idx], z[idx], method="ksg")
    assert len(_repeat_warnings(rec)) == 1
    with pytest.warns(BiasRuleWarning) as rec:
        MutualInformation("ksg").fit(x[idx]).score(y[idx])
    assert len(_repeat_warnings(rec)) == 1


@pytest.mark.parametrize("case", ["clean", "below 1 %", "rounded", "kde", "histogram",
                                  "gaussian"])
def test_not_judged(case):
    rng, x, y = _pair()
    method = case if case in ("kde", "histogram", "gaussian") else "ksg"
    if case == "below 1 %":
        idx = _repeated(rng, 0.005)
        x, y = x[idx], y[idx]
    elif case == "rounded":  # ties across different rows: the discrete pair's MI
        x, y = np.round(x, 1), np.round(y, 1)
    elif case in ("kde", "histogram", "gaussian"):
        x, y = np.repeat(x, 2), np.repeat(y, 2)
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        value = mutual_information(x, y, method=method)
    assert _repeat_warnings(rec) == []
    assert abs(value - EXACT) < 0.05  # these estimates are right: nothing to say
