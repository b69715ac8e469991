"""A bare Predictor fitted on a run's log is refused in a loop of other conditions (fix54-b).

Reference: the definition of the training set shared by both paths, the POL of a run "of
the same conditions" (``training_conditions``: telescope, layers, sensors, mirrors,
frame clock; the controller and seed may differ), and the LoopPredictor path's own
refusal (tests/closedloop/test_trained_conditions_audit10.py). Round 53 PART a, C16 /
C22: ``LoopPredictor.from_name('linear-ls').trained(run A)`` was refused at r0 5 cm
where ``make_predictor('linear-ls').fit(run A's POL)`` ran without a word. A predictor
fitted on the run's ``ModalLog`` now keeps the log's metadata (the run's config) and
``simulate`` applies the same check; one fitted on a bare array carries no conditions
and runs as before (documented).
"""

import dataclasses

import numpy as np
import pytest

from closedloop import LoopPredictor, simulate
from modalinfo.forecast import make_predictor

from .conftest import lag_only


@pytest.fixture(scope="module")
def runs():
    cfg = lag_only()
    stronger = cfg.replace(layers=tuple(dataclasses.replace(lay, d_over_r0=1.25 * lay.d_over_r0)
                                        for lay in cfg.layers))
    return cfg, stronger, simulate(cfg, 0.12, seed=0)


def test_bare_predictor_refused_like_a_loop_predictor(runs):
    cfg, stronger, ref = runs
    bare = make_predictor("linear-ls").fit(ref.logs["dm0.pol"])
    assert bare.training_metadata_["source"] == "closedloop"
    with pytest.raises(ValueError, match=r"`layers` is not this config's"):
        simulate(stronger, 0.01, predictor=bare, seed=0)
    # the same refusal as the LoopPredictor path on the same run
    spec = LoopPredictor.from_name("linear-ls").trained(ref)
    with pytest.raises(ValueError, match=r"`layers` is not this config's"):
        simulate(stronger, 0.01, predictor=spec, seed=0)


def test_bare_predictor_same_conditions_runs(runs):
    cfg, _, ref = runs
    bare = make_predictor("linear-ls").fit(ref.logs["dm0.pol"])
    other = cfg.replace(loop=dataclasses.replace(cfg.loop, gain=0.3))  # the controller
    r = simulate(other, 0.01, predictor=bare, seed=1)
    assert np.all(np.isfinite(r.strehl))


def test_fit_on_log_equals_fit_on_its_values(runs):
    _, _, ref = runs
    log = ref.logs["dm0.pol"]
    a = make_predictor("linear-ls").fit(log)
    b = make_predictor("linear-ls").fit(np.asarray(log.coeffs))
    assert all(np.array_equal(a.params_[k], b.params_[k]) for k in a.params_)
    assert a.columns_ == list(log.labels)
    assert not hasattr(b, "training_metadata_")
    # an array carries no conditions: runs as before, unchecked
    assert LoopPredictor.from_fitted(b).trained_on is None
