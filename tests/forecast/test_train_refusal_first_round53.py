"""Too few training frames for one predictor is refused before any predictor is fitted.

Round 53 PART b, W09: ``modalinfo forecast`` of a 1,000-mode log fitted the linear,
ARMA and neural-net predictors (6 min of wall time) before the multivariate one refused
its 1,000 training frames. Reference: ``MultivariatePredictor(order=2).min_samples(M)``,
the predictor's own rule (here order + 10 x order x M = 2 + 10 x 2 x 30 = 602 rows > the
300 training frames), and the count of ``fit`` calls (none may happen).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, MultivariatePredictor, evaluate


def test_refused_before_any_fit(monkeypatch):
    x = np.random.default_rng(0).standard_normal((600, 30))
    multi = MultivariatePredictor(order=2)
    assert multi.min_samples(30) > 300
    fitted = []
    original = LinearPredictor.fit

    def counted(self, history):
        fitted.append(type(self).__name__)
        return original(self, history)

    monkeypatch.setattr(LinearPredictor, "fit", counted)
    with pytest.raises(ValueError, match="needs at least .* for MultivariatePredictor"):
        evaluate({"linear": LinearPredictor(fit_weights=True), "multi": multi}, x, train=300,
                 horizons=[1])
    assert fitted == []  # the linear predictor was fitted first, then the refusal came
