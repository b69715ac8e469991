"""Round 8 of issue 27's adversarial inputs (orderings): failures, fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 8, issue 27".

Reference: the documented contract of ``order_modes`` (``estimator``: a registered
method name or an object with fit/score; an unknown option raises TypeError), which
holds for every ``method``, also those that order without an estimator.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import order_modes
from modalinfo.telemetry import ModalLog


@pytest.fixture(scope="module")
def log_and_basis():
    c = np.random.default_rng(4).standard_normal((200, 3))
    return ModalLog(c, rate=1e3, modes=[2, 3, 4]), ZernikeBasis(Pupil(16), [2, 3, 4])


@pytest.mark.parametrize("method", ["standard", "variance", "pca"])
def test_a_misspelt_estimator_is_refused_by_every_method(log_and_basis, method):
    # b03: method='standard' accepted estimator='bogus' without a word
    log, basis = log_and_basis
    with pytest.raises(ValueError, match=r"`method` must be one of"):
        order_modes(log, basis, method, estimator="bogus", n_resamples=0)


def test_an_unknown_estimator_option_is_refused_by_every_method(log_and_basis):
    # b04: estimator_options={'nope': 1} accepted by method='standard'
    log, basis = log_and_basis
    with pytest.raises(TypeError, match=r"does not accept option\(s\) nope"):
        order_modes(log, basis, "standard", estimator_options={"nope": 1}, n_resamples=0)


def test_a_valid_estimator_still_orders(log_and_basis):
    log, basis = log_and_basis
    assert order_modes(log, basis, "standard", estimator="ksg", n_resamples=0).order.tolist() == [
        0, 1, 2]
