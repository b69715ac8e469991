"""Fixes 41-c (issue 27): the KSG temporal-neighbour rule on every CMI / TE road.

Fixes 40-b put ``ksg.ksg_temporal_why`` (the KSG CMI again with each sample's
neighbours within 5 rows left out; warned where it drops by more than max(0.05 nats,
10 %)) on ``transfer_entropy`` and ``conditional_mutual_information`` only, and left
``transfer_entropy_map`` and ``select_inputs`` silent on the same estimate: a smooth
target (AR(2), double root 0.99) and an independent AR(1) 0.99 source read a KSG TE of
+0.45 nats (truth 0) in the map's cell, and ``select_inputs`` picked that source as an
input with the same gain, each without the word ``transfer_entropy`` gives. Now the map
judges each target's largest cell and the selection each gain the effective-sample
rule passes (one warning per call, naming each rule that failed).

References: truth 0 for independent series (the source and the target are drawn
apart); ``transfer_entropy``'s own warning on the same cell (the road the rule was
measured on, docs/ADVERSARIAL.md "Fixes 40-b"); white series (truth 0, no temporal
neighbours) for the quiet guards.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from modalinfo.information import (
    BiasRuleWarning,
    select_inputs,
    transfer_entropy,
    transfer_entropy_map,
)

from .test_effective_sample_roads_fix40a import ROADS as EFFECTIVE_SAMPLE_ROADS
from .test_ksg_temporal_neighbours_fix40b import _ar1, _smooth  # n = 2000 by default

N = 2000


def _caught(f):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        value = f()
    return value, [str(m.message) for m in w if issubclass(m.category, BiasRuleWarning)]


def _planted(seed):
    """(target, source): a smooth target and an independent persistent source."""
    rng = np.random.default_rng(seed)
    source, target = _ar1(rng, 0.99), _smooth(rng, 0.99)
    return target, source


#: every road of ``test_effective_sample_roads_fix40a.ROADS`` whose KSG estimate is a
#: CMI / TE of time-ordered rows, with its planted call on the smooth target
ROADS = {
    "transfer_entropy": lambda t, s: transfer_entropy(s, t, history=1),
    "conditional_mutual_information": None,  # tests/information/test_ksg_temporal_...40b
    "transfer_entropy_map": lambda t, s: transfer_entropy_map(
        np.column_stack([t, s]), lags=1, history=1, method="ksg", n_surrogates=0),
    "select_inputs": lambda t, s: select_inputs(
        np.column_stack([t, s]), target=0, max_lag=1, method="ksg", n_surrogates=19),
}
#: the other roads, and why the rule is not theirs
OTHERS = {
    # the MI of a pair is judged by the effective-sample rule (a smooth series' pairs
    # hold < 20 effective samples), which speaks first on every road
    "mutual_information", "MutualInformation",
}


def test_every_estimator_road_is_classified():
    assert set(EFFECTIVE_SAMPLE_ROADS) - set(ROADS) - OTHERS == set()


@pytest.mark.parametrize("seed", [9201, 9204])
@pytest.mark.parametrize("road", ["transfer_entropy", "transfer_entropy_map",
                                  "select_inputs"])
def test_each_road_warns_on_the_smooth_target(road, seed):
    target, source = _planted(seed)
    te_value, te_msgs = _caught(lambda: transfer_entropy(source, target, history=1))
    assert len(te_msgs) == 1 and "Theiler window" in te_msgs[0]  # the reference road
    value, msgs = _caught(lambda: ROADS[road](target, source))
    assert len(msgs) == 1, msgs  # one warning per call
    assert "Theiler window" in msgs[0]  # fails before on the map and the selection
    if road == "transfer_entropy_map":
        assert "1 of 2 target(s) fail the temporal-neighbour rule" in msgs[0]
        # the cell judged is the one transfer_entropy estimates: the same KSG value
        assert value.te[1, 0, 0] == pytest.approx(te_value, rel=1e-12)
        assert value.te[1, 0, 0] > 0.3  # truth 0: the bias the warning names
    if road == "select_inputs":
        assert [i.label for i in value.inputs] == ["m0[t]", "m1[t]"]  # the spurious input
        assert "gains fail the temporal-neighbour rule" in msgs[0]
        assert value.inputs[1].gain > 0.3  # truth 0


def test_selection_names_both_rules_in_one_warning():
    # the first gain (the target's own lag, both smooth: ~0 effective samples) fails the
    # effective-sample rule, the source's gain given it the temporal one
    target, source = _planted(9201)
    _, msgs = _caught(lambda: ROADS["select_inputs"](target, source))
    assert len(msgs) == 1
    assert "1 of 2 gains fail the effective-sample rule" in msgs[0]
    assert "1 of 2 gains fail the temporal-neighbour rule" in msgs[0]


@pytest.mark.parametrize("seed", [1, 2])
def test_white_series_quiet_with_the_ksg(seed):
    s = np.random.default_rng(seed).standard_normal((N, 2))
    assert _caught(lambda: transfer_entropy_map(s, lags=1, history=1, method="ksg",
                                                n_surrogates=0))[1] == []
    assert _caught(lambda: select_inputs(s, target=0, max_lag=1, method="ksg",
                                         n_surrogates=19))[1] == []


def test_the_other_methods_are_not_judged_by_the_ksg_rule():
    # the Gaussian map of the same smooth cell: the KSG rule is the KSG's
    target, source = _planted(9201)
    _, msgs = _caught(lambda: transfer_entropy_map(np.column_stack([target, source]),
                                                   lags=1, history=1, n_surrogates=0))
    assert not any("Theiler" in m for m in msgs)


def test_a_piled_persistent_target_is_warned_once():
    """One warning per call (review note "select_inputs can warn twice", fixes 41-c).

    An AR(1) 0.999 target with 50 of its 1000 frames written as 0.0 (a 5 % pile inside
    its range, above the 3 % rule) and ~15 effective pairs with its own lag (Bartlett,
    fewer than 20): the pile's warning and the effective-sample one were both given;
    now the pile's only, as ``transfer_entropy``'s point estimate of a piled variable.
    """
    rng = np.random.default_rng(7)
    x = _ar1(rng, 0.999, n=1000)
    x[400:450] = 0.0
    series = np.column_stack([x, _ar1(rng, 0.999, n=1000)])
    _, msgs = _caught(lambda: select_inputs(series, target=0, max_lag=1,
                                            method="histogram", n_surrogates=19))
    assert len(msgs) == 1, msgs  # fails before: 2
    assert "5.0% of its samples at 0" in msgs[0]
