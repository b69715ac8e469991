"""A fitted predictor of another mode count is refused before the loop (round 9, row
c-fitted-wrong-modes).

Reference: the loop's mode count, ``LoopModel(config).n_modes`` (the lag-only loop's zonal
mirror). An ARMA fitted on 3 modes was refused at frame 0 with "`x_t` must have shape
(3,)", naming an argument the caller never gave; now ``predictor`` is named with both
counts, and a predictor fitted on the loop's own POL (the same count) runs.
"""

import numpy as np
import pytest

from closedloop import LoopModel, LoopPredictor, simulate
from modalinfo.forecast import ARMAPredictor

from .conftest import lag_only


def test_mode_count_checked_before_the_loop():
    cfg = lag_only()
    n = LoopModel(cfg).n_modes
    wrong = ARMAPredictor(order=(1, 0)).fit(np.random.default_rng(0).standard_normal((200, 3)))
    with pytest.raises(ValueError, match=f"`predictor` was fitted on 3 mode.*feeds it {n}"):
        simulate(cfg, 0.01, predictor=LoopPredictor.from_fitted(wrong), seed=0)
    ref = simulate(cfg, 0.12, seed=0)
    right = LoopPredictor.from_name("linear-ls").trained(ref)
    assert simulate(cfg, 0.01, predictor=right, seed=0).strehl.shape[0] == 10
