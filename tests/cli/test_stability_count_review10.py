"""``reorder --stability`` counts every ordering it runs as the greedy search it is.

Round 10 of planted bugs (review10). Reference, from outside
:mod:`modalinfo.ordering.cost`: the count of MI estimates of one greedy ordering of M
modes with every mode left scored at every step, ``M + (M - 1) + ... + 2 = M (M + 1) / 2
- 1`` (377 for 27 modes; tests/ordering/test_least_time_structure.py counts a real
run's calls), and what ``--stability W`` runs on T frames (module notes of
:mod:`modalinfo.cli.cmd_reorder`): the whole log once, ``T // W`` windows and the whole
log again for 3 seeds. Planted bug R10-C6 (the 3 seeds' orderings counted as
``mi_marginal``, ``2 M - 2`` = 52 each) escaped tests/cli/test_adversarial_round10.py,
whose limit of 1.5 orderings was crossed either way.
"""

from __future__ import annotations

import argparse

import pytest

from modalinfo.cli.cmd_reorder import check_mi_time
from modalinfo.common.cli import CommandError


class _Log:
    def __init__(self, n_frames, n_modes):
        self.n_frames, self.n_modes = n_frames, n_modes


@pytest.mark.parametrize(("frames", "window"), [(4000, 2000), (4000, 1000)])
def test_every_ordering_of_stability_is_counted_as_a_greedy_one(monkeypatch, frames, window):
    from modalinfo.ordering import cost

    monkeypatch.setattr(cost, "MAX_ORDERING_SECONDS", 0.0)  # refuse, to read the count
    args = argparse.Namespace(estimator="histogram", budget=200_000, frame=None,
                              pupil_pixels=64, resamples=0, stability=window,
                              method="mi_greedy")
    greedy = sum(range(2, 28))  # 27 modes: 27 + 26 + ... + 2 estimates
    assert greedy == 377
    orderings = 1 + frames // window + 3
    with pytest.raises(CommandError, match=f"at least {orderings * greedy} estimates "):
        check_mi_time(args, _Log(frames, 27))
