"""The KSG temporal rule on the map / selection roads: the value judged, its options (review27).

Planted bugs of review27 (docs/MUTATION.md, round 27) that the fixes-41-c file let
through: the map's cell handed to the rule in the wrong units (``value * factor`` for
``value / factor``: every test ran in nats, factor 1), the selection's gains judged
with the first gain's value, and ``fallback`` passed on to the rule (a TypeError where
the map or the selection is called with the documented ``fallback`` option).

References, from outside the roads judged: ``transfer_entropy`` (the road the rule was
measured on, fixes 40-b), whose warning quotes "the KSG estimate X nats" for the same
cell; the selection's own reported gain [nats]; ``method='ksg'``'s documented options
(``copula, fallback, k, seed``).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from modalinfo.information import select_inputs, transfer_entropy, transfer_entropy_map

from .test_ksg_temporal_roads_fix41c import _caught, _planted


def _quoted(msg):
    return float(re.search(r"the KSG estimate (\S+) nats", msg).group(1))


def test_the_map_in_bits_judges_the_cell_in_nats():
    target, source = _planted(9201)
    te_nats, te_msgs = _caught(lambda: transfer_entropy(source, target, history=1))
    m, msgs = _caught(lambda: transfer_entropy_map(
        np.column_stack([target, source]), lags=1, history=1, method="ksg",
        n_surrogates=0, units="bits"))
    assert m.te[1, 0, 0] == pytest.approx(te_nats / np.log(2.0), rel=1e-12)
    assert len(msgs) == 1 and "temporal-neighbour rule" in msgs[0], msgs
    # the value quoted is the cell in nats, as transfer_entropy quotes it
    assert _quoted(msgs[0]) == pytest.approx(_quoted(te_msgs[0]), rel=0, abs=0)
    assert _quoted(msgs[0]) == pytest.approx(te_nats, rel=5e-3)


def test_the_selection_judges_each_gain_with_its_own_value():
    target, source = _planted(9201)
    result, msgs = _caught(lambda: select_inputs(
        np.column_stack([target, source]), target=0, max_lag=1, method="ksg",
        n_surrogates=19))
    assert len(msgs) == 1 and "1 of 2 gains fail the temporal-neighbour rule" in msgs[0]
    gains = [i.gain for i in result.inputs]
    assert abs(gains[0] - gains[1]) > 0.1  # the planted swap is visible
    assert _quoted(msgs[0]) == pytest.approx(gains[1], rel=5e-3)


@pytest.mark.parametrize("road", ["map", "selection"])
def test_the_fallback_option_is_accepted_and_the_rule_still_speaks(road):
    target, source = _planted(9201)
    series = np.column_stack([target, source])
    if road == "map":
        call = lambda: transfer_entropy_map(series, lags=1, history=1, method="ksg",  # noqa: E731
                                            n_surrogates=0, fallback="none")
    else:
        call = lambda: select_inputs(series, target=0, max_lag=1, method="ksg",  # noqa: E731
                                     n_surrogates=19, fallback="none")
    _, msgs = _caught(call)
    assert len(msgs) == 1 and "Theiler window" in msgs[0], msgs
