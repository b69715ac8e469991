"""Warnings name the caller's line, whatever the route (adversarial round 24 PART a).

Reference: Python's ``warnings`` contract, outside the code: a library's warning is
attributed (``filename``, ``lineno``) to the line of the user's call, the frame a
``stacklevel`` is meant to reach. Before the fix a fixed ``stacklevel`` was right for
one route only: ``mutual_information(..., k=n - 1)`` and ``MutualInformation.estimate``
named ``information/api.py``, ``bins=60`` named ``api.py`` through ``mutual_information``
(rows W01-W03, W10), and ``evaluate`` on a log whose rate changes named
``forecast/evaluate.py`` (W21). Each case asserts the recorded warning's file is this
test file and its line the call's line (read from the frame, not typed).
"""

from __future__ import annotations

import inspect
import warnings

import numpy as np
import pytest

from modalinfo.forecast import PersistencePredictor, evaluate
from modalinfo.information import BiasRuleWarning, MutualInformation, mutual_information
from modalinfo.telemetry import ModalLog


def _pair(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return rng.multivariate_normal([0.0, 0.0], [[1.0, 0.6], [0.6, 1.0]], n).T


def _where(call) -> tuple[list, int]:
    """Run ``call`` (a lambda on the line after this call's) recording every warning."""
    line = inspect.currentframe().f_back.f_lineno
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        call()
    return caught, line


def _assert_here(caught: list, line: int, category: type[Warning]) -> None:
    mine = [w for w in caught if issubclass(w.category, category)]
    assert mine, [str(w.message) for w in caught]
    for w in mine:
        assert (w.filename, w.lineno) == (__file__, line), (w.filename, w.lineno, str(w.message))


@pytest.mark.parametrize("route", ["function", "class"])
@pytest.mark.parametrize("options", [{"method": "ksg", "k": 199},
                                     {"method": "kde", "bandwidth": 0.001},
                                     {"method": "histogram", "bins": 60}])
def test_bias_rule_warning_names_the_callers_line(route, options):
    x, y = _pair(200)
    if route == "function":
        caught, line = _where(lambda: mutual_information(x, y, **options))
    else:
        method = options["method"]
        rest = {k: v for k, v in options.items() if k != "method"}
        caught, line = _where(lambda: MutualInformation(method, **rest).estimate(x, y))
    _assert_here(caught, line, BiasRuleWarning)


def test_rate_change_warning_of_evaluate_names_the_callers_line():
    rng = np.random.default_rng(1)
    coeffs = rng.standard_normal((400, 2)).cumsum(axis=0) * 0.1
    times = np.cumsum(np.r_[np.full(200, 1e-3), np.full(200, 1.01e-3)])
    log = ModalLog(coeffs, timestamps=times)
    caught, line = _where(lambda: evaluate({"p": PersistencePredictor()}, log, horizons=[1]))
    assert any("equally spaced" in str(w.message) for w in caught)
    _assert_here([w for w in caught if "equally spaced" in str(w.message)], line, UserWarning)
