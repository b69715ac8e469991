"""MI options given to an ordering that estimates no MI are refused (adversarial round 36
PART a, M4-M6, left then; issue 27, fix38-c).

``order_modes(..., "standard" | "variance" | "pca")`` accepted ``estimator_options``,
``confidence_level`` and ``block_length`` it cannot use, and recorded the defaults.
Now refused when the caller set them, naming the argument and the method.
``compare_orderings`` passes its ``estimator_options`` to the MI specs only, so a
comparison mixing "variance" and "mi_marginal" with options still runs. Reference for
its results: the variance order is numpy's ``argsort`` of the columns' mean squares
(the documented rule), and the MI entry equals ``order_modes`` called alone with the
same options and seed.
"""


import numpy as np
import pytest

from modalinfo.ordering import order_modes
from modalinfo.ordering.compare import basis_for_log, compare_orderings
from modalinfo.telemetry import ModalLog

MODES = list(range(2, 9))


pytestmark = pytest.mark.usefixtures("quiet_warnings")


def _log():
    rng = np.random.default_rng(0)
    a = rng.standard_normal((600, len(MODES))) * np.linspace(0.3, 1.0, len(MODES))
    return ModalLog(a, rate=1000.0, modes=MODES, units="rad")


@pytest.mark.parametrize("method", ["standard", "variance", "pca"])
@pytest.mark.parametrize("option, value", [("estimator_options", {"bins": 16}),
                                           ("confidence_level", 0.9),
                                           ("block_length", 5)])
def test_an_option_the_method_cannot_use_is_refused(method, option, value):
    log = _log()
    basis = basis_for_log("zernike", log, n_pixels=24)
    with pytest.raises(ValueError, match=rf"`{option}`=.*method='{method}'"):
        order_modes(log, basis, method, **{option: value})


@pytest.mark.parametrize("method", ["standard", "variance", "pca"])
def test_the_defaults_and_an_empty_dict_still_run(method):
    log = _log()
    # "pca" orders a data K-L basis (its coefficients uncorrelated)
    basis = basis_for_log("kl-data" if method == "pca" else "zernike", log, n_pixels=24)
    res = order_modes(log, basis, method, estimator_options={}, confidence_level=0.95,
                      block_length=None)
    assert sorted(res.order.tolist()) == list(range(len(MODES)))


def test_compare_passes_the_options_to_the_mi_specs_only():
    log = _log()
    comp = compare_orderings(log, "zernike:variance,zernike:mi_marginal",
                             estimator_options={"bins": 16}, sample_budget=2000, seed=0,
                             n_pixels=24)
    variance, mi = (e.ordering for e in comp.entries)
    x = np.asarray(log.coeffs)
    expected = [f"Z{MODES[j]}" for j in np.argsort(-np.mean(x * x, axis=0), kind="stable")]
    assert list(variance.labels) == expected
    alone = order_modes(log, basis_for_log("zernike", log, n_pixels=24), "mi_marginal",
                        estimator_options={"bins": 16}, sample_budget=2000, seed=0,
                        n_resamples=0)
    assert mi.labels == alone.labels and mi.estimator_options == {"bins": 16}
    np.testing.assert_array_equal(mi.scores, alone.scores)
