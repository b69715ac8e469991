"""Plug-in estimators that misbehave are named, not carried (adversarial round 13, PART a).

References (outside the code under test): a mutual information is a real number that is
never negative (Cover & Thomas 2006, Theorem 2.6.3) and is the same for the same data;
numpy's read-only flag (a write raises ``ValueError``) and the caller's bytes (hashed
before and after) tell whether a plug-in could change the caller's array. Each plug-in
below wraps the built-in histogram engine and breaks one of these on purpose; before the
round-13 fixes each returned a number (or an unexplained ``float()`` error).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.information import (
    MIMethod,
    conditional_mutual_information,
    entropy,
    mutual_information,
    register_method,
    transfer_entropy,
    unregister_method,
)
from modalinfo.information.histogram import HistogramEngine
from modalinfo.ordering import order_modes
from modalinfo.telemetry.synthetic import kaos_like


class _Engine:
    """The histogram's MI; ``bad`` maps the honest score to a broken answer."""

    bad = staticmethod(lambda v: v)

    def __init__(self, **options):
        self._engine = HistogramEngine()

    def fit(self, x):
        self._engine.fit(x)
        return self

    def score(self, y):
        return type(self).bad(self._engine.score(y))


def _engine(bad):
    return type("Broken", (_Engine,), {"bad": staticmethod(bad)})


_RNG = np.random.default_rng(0)
_BROKEN = {
    "nan": (_engine(lambda v: float("nan")), ValueError, "returned NaN"),
    "inf": (_engine(lambda v: float("inf")), ValueError, "returned inf"),
    "negative": (_engine(lambda v: -0.5), ValueError, "never negative"),
    "string": (_engine(lambda v: str(v)), TypeError, "must return a real number"),
    "bool": (_engine(lambda v: True), TypeError, "must return a real number"),
    "list": (_engine(lambda v: [v]), TypeError, "must return a real number"),
    "complex": (_engine(lambda v: complex(v, 0)), TypeError, "must return a real number"),
    "random": (_engine(lambda v: v + _RNG.random()), ValueError, "not deterministic"),
}


@pytest.fixture(scope="module")
def pair():
    rng = np.random.default_rng(1)
    return rng.multivariate_normal([0, 0], [[1, 0.6], [0.6, 1]], 2000).T


@pytest.fixture(scope="module")
def small_log():
    log = kaos_like(1500, seed=1).select(modes=[2, 3, 4, 5])
    return log, ZernikeBasis(Pupil(24, diameter=0.7), modes=log.modes)


@pytest.mark.parametrize("kind", sorted(_BROKEN))
def test_registered_engine_answer_is_checked(pair, kind):
    engine, error, words = _BROKEN[kind]
    register_method(MIMethod(name=f"r13-{kind}", engine=engine))
    try:
        with pytest.raises(error, match=f"method='r13-{kind}'.*{words}"):
            mutual_information(*pair, method=f"r13-{kind}")
    finally:
        unregister_method(f"r13-{kind}")


@pytest.mark.parametrize("kind", sorted(_BROKEN))
def test_estimator_object_in_ordering_is_checked(small_log, kind):
    engine, error, words = _BROKEN[kind]
    log, basis = small_log
    if kind == "nan":  # NaN is "this candidate cannot be scored" to the ordering
        words = "no finite score"
    with pytest.raises(error, match=words):
        order_modes(log, basis, method="mi_greedy", estimator=engine(), seed=0)


def test_honest_plugin_unchanged(pair, small_log):
    register_method(MIMethod(name="r13-honest", engine=_Engine))
    try:
        # the histogram engine's value, bit for bit, and near the Gaussian closed form
        value = mutual_information(*pair, method="r13-honest")
        assert value == mutual_information(*pair, method="histogram")
        assert value == pytest.approx(-0.5 * np.log(1 - 0.36), abs=0.05)
    finally:
        unregister_method("r13-honest")
    log, basis = small_log
    ours = order_modes(log, basis, method="mi_greedy", estimator=_Engine(), seed=0)
    builtin = order_modes(log, basis, method="mi_greedy", estimator="histogram", seed=0)
    assert ours.labels == builtin.labels


def test_plugin_cannot_change_the_callers_array(pair):
    class Doubler(_Engine):
        def fit(self, x):
            x *= 2.0
            return super().fit(x)

    register_method(MIMethod(name="r13-mutates", engine=Doubler))
    x = pair[0].copy()
    before = x.tobytes()
    try:
        with pytest.raises(ValueError, match="read-only"):
            mutual_information(x, pair[1], method="r13-mutates")
    finally:
        unregister_method("r13-mutates")
    assert x.tobytes() == before


def test_plugin_entropy_and_cmi_answers_are_checked(pair):
    x, y = pair
    z = np.random.default_rng(2).normal(size=x.size)
    register_method(MIMethod(name="r13-ent", engine=_Engine, entropy=lambda x: float("nan"),
                             cmi=lambda x, y, z: -3.0))
    try:
        with pytest.raises(ValueError, match="its entropy\\(\\) returned NaN"):
            entropy(x, method="r13-ent")
        with pytest.raises(ValueError, match="its cmi\\(\\) returned -3 nats.*never negative"):
            conditional_mutual_information(x, y, z, method="r13-ent")
    finally:
        unregister_method("r13-ent")


def test_bias_rule_must_return_a_sentence(pair):
    x, y = pair
    z = np.random.default_rng(2).normal(size=x.size)
    register_method(MIMethod(name="r13-rule", engine=_Engine, cmi=lambda x, y, z: 0.1,
                             bias_rule=lambda n, d, options: 5))
    try:
        with pytest.raises(TypeError, match="bias_rule of MI method 'r13-rule' must return None"):
            conditional_mutual_information(x, y, z, method="r13-rule")
    finally:
        unregister_method("r13-rule")


def test_method_without_cmi_is_named(pair):
    register_method(MIMethod(name="r13-mi-only", engine=_Engine))
    try:
        with pytest.raises(ValueError, match="'r13-mi-only' is registered with no `cmi`"):
            transfer_entropy(*pair, method="r13-mi-only")
    finally:
        unregister_method("r13-mi-only")
