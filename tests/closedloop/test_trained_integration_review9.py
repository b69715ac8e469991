"""A predictor trained on a reference of another WFS integration time is refused.

Round 9 of planted bugs (review9, bug F1): ``training_conditions`` lists the frame
clock as ``loop.time_step`` *and* ``loop.integration_time`` (docstring: "a forecaster's
lags count frames"); the existing tests changed the time step together with the
integration, so dropping the integration time from the conditions went unseen.
Reference: the training set's definition (the POL of a run of the same conditions) and,
measured here, that a half-frame exposure gives another POL series and other
least-squares weights (numpy: the fitted parameters differ), so the forecaster would
model another series.
"""

import numpy as np
import pytest

from closedloop import LoopPredictor, run_trained, simulate

from .conftest import lag_only


@pytest.fixture(scope="module")
def refs():
    cfg = lag_only()
    short = lag_only(integration=0.5e-3)
    assert short.loop.time_step == cfg.loop.time_step  # only the exposure differs
    return cfg, simulate(cfg, 0.12, seed=0), short, simulate(short, 0.12, seed=0)


def test_half_frame_exposure_is_another_model(refs):
    _, ref, _, ref_short = refs
    assert not np.array_equal(ref.logs["dm0.pol"].coeffs, ref_short.logs["dm0.pol"].coeffs)
    a = LoopPredictor.from_name("linear-ls").trained(ref).predictor.params_
    b = LoopPredictor.from_name("linear-ls").trained(ref_short).predictor.params_
    assert not all(np.array_equal(a[k], b[k]) for k in a)


def test_reference_of_another_exposure_refused(refs):
    cfg, _, short, ref_short = refs
    with pytest.raises(ValueError, match=r"`loop.integration_time` is not this config's"):
        run_trained(cfg, "linear-ls", 0.01, seed=0, reference=ref_short)
    spec = LoopPredictor.from_name("linear-ls").trained(ref_short)
    with pytest.raises(ValueError, match=r"`predictor` 'linear-ls' was trained"):
        simulate(cfg, 0.01, predictor=spec, seed=0)
    # the config it was trained on accepts it
    r = simulate(short, 0.005, predictor=spec, seed=1)
    assert np.all(np.isfinite(r.strehl))
