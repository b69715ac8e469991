"""``evaluate`` estimates its predictors' fit time before any work (round 48 PART a, O10).

An ARMA evaluation of 3,000 frames x 1,600 modes ran 150 s with no estimate, warning or
progress. ``Predictor.fit_seconds`` (ARMA: ``M x (a + b T)`` of ``FIT_SECONDS``) summed
over the fit and the scheduled refits is refused above ``max_seconds`` and warned above
a minute (``check_ordering_seconds``, the rule of ``order_modes``). References: the
arithmetic of the documented formula and the refit count enumerated by brute force over
the frames (``Predictor._feed``'s rule: multiples of ``refit_every``, at least ``window``,
at most the last origin); no timing is asserted.
"""

from __future__ import annotations

import numpy as np
import pytest

import modalinfo.ordering.cost as cost
from modalinfo.cli import main
from modalinfo.forecast import ARMAPredictor, evaluate
from modalinfo.forecast.arma import FIT_SECONDS
from modalinfo.forecast.evaluate import _fits
from modalinfo.forecast.persistence import PersistencePredictor


@pytest.mark.parametrize(("order", "key", "scale"), [((2, 3), "arma", 1.0), ((3, 0), "ar", 1.0),
                                                     ("aic", "search", 1.0)])
def test_fit_seconds_formula(order, key, scale):
    a, b = FIT_SECONDS[key]
    pred = ARMAPredictor(order=order)
    assert pred.fit_seconds(1500, 1600) == pytest.approx(1600 * scale * (a + b * 1500),
                                                         rel=1e-12)
    assert ARMAPredictor(order="aic", max_order=2).fit_seconds(100, 10) == pytest.approx(
        10 * 9 / 36 * (FIT_SECONDS["search"][0] + FIT_SECONDS["search"][1] * 100), rel=1e-12)
    assert PersistencePredictor().fit_seconds(10**6, 10**4) == 0.0


@pytest.mark.parametrize(("n_train", "refit", "window", "last"),
                         [(200, None, None, 398), (200, 50, None, 398), (200, 50, 120, 398),
                          (200, 70, 30, 399), (200, 1000, None, 398)])
def test_fit_count_against_enumeration(n_train, refit, window, last):
    pred = ARMAPredictor(refit_every=refit, window=window)
    w = n_train if window is None else window
    expected = 1 + (0 if refit is None else
                    sum(1 for n in range(1, last + 1) if n % refit == 0 and n >= w))
    assert _fits(pred, n_train, last) == expected


def test_refused_before_any_fit(monkeypatch):
    calls = []
    monkeypatch.setattr(ARMAPredictor, "fit", lambda self, *a, **k: calls.append(1))
    x = np.random.default_rng(0).standard_normal((300, 4))
    with pytest.raises(ValueError, match=r"estimated at .* of CPU.*more than `max_seconds`"
                                         r"=1e-06.*raise `max_seconds`"):
        evaluate({"arma": ARMAPredictor()}, x, horizons=1, max_seconds=1e-6)
    assert calls == []


def test_warned_once_above_the_note(monkeypatch):
    monkeypatch.setattr(cost, "NOTE_ORDERING_SECONDS", 1e-9)
    x = np.random.default_rng(0).standard_normal((300, 2))
    with pytest.warns(cost.OrderingCostWarning) as record:
        evaluate({"arma": ARMAPredictor(order=(1, 0))}, x, horizons=1)
    costs = [w for w in record if issubclass(w.category, cost.OrderingCostWarning)]
    assert len(costs) == 1 and "evaluate's fits ('arma' 1 fit(s)" in str(costs[0].message)


def test_cli_refusal_is_one_line(tmp_path, capsys):
    path = tmp_path / "log.npy"
    np.save(path, np.random.default_rng(0).standard_normal((300, 3)))
    code = main(["forecast", str(path), "--predictors", "arma", "--horizon", "1",
                 "--max-seconds", "1e-6"])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and "--max-seconds" in err and "Traceback" not in err
