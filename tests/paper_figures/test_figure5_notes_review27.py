"""Figure 5 turns only the declined skill test into a note; other warnings are shown (review27).

Planted bug of review27 (docs/MUTATION.md, round 27, P1) that the fixes-41-c file let
through: ``recording()`` of every warning around ``evaluate`` in ``fig5_forecast.compute``
(for ``recording(message="evaluate: no honest Diebold-Mariano")``) wrote any warning of
the evaluation to stderr as "Figure 5: note" and hid it from the warnings machinery.
Reference: the module's comment ("a declined skill test is a note of the run; every
other warning is shown as usual") and Python's ``catch_warnings(record=True)``. The
predictors are stubbed by the ``cheap_figure5_predictors`` fixture (tests/conftest.py)
(their fits are not the test's); ``evaluate`` is the real one, wrapped to warn first;
the figure stops after the notes are written.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from modalinfo.common.quiet import warn
from modalinfo.telemetry import ModalLog


def test_only_the_declined_skill_test_is_a_note(monkeypatch, capsys, cheap_figure5_predictors):
    import modalinfo.forecast as forecast
    from paper_figures import fig5_forecast as fig5

    real = forecast.evaluate

    def evaluate(*args, **kwargs):
        warn("evaluate: no honest Diebold-Mariano test for the stub", UserWarning,
             stacklevel=2)
        warn("evaluate: the Diebold-Mariano p-value of 1 predictor-horizon pair(s) may be "
             "too small: the stub", UserWarning, stacklevel=2)  # stop 53: a note too
        warn("the stub's other warning", RuntimeWarning, stacklevel=2)
        return real(*args, **kwargs)

    monkeypatch.setattr(forecast, "evaluate", evaluate)

    class StopError(Exception):
        pass

    def stop(*args, **kwargs):  # the rest of the figure is not the test's
        raise StopError

    monkeypatch.setattr(fig5, "_increment_correlation", stop)
    log = ModalLog(np.random.default_rng(4).standard_normal((fig5.MIN_FRAMES, 2)),
                   rate=1000.0, modes=[2, 3], units="rad")
    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        with pytest.raises(StopError):
            fig5.compute(log, quick=True)
    err = capsys.readouterr().err
    assert "Figure 5: evaluate: no honest Diebold-Mariano test for the stub" in err
    assert "Figure 5: evaluate: the Diebold-Mariano p-value of 1 predictor-horizon" in err
    assert not [w for w in shown if "may be too small" in str(w.message)]
    assert "the stub's other warning" not in err
    assert [str(w.message) for w in shown
            if w.category is RuntimeWarning] == ["the stub's other warning"]
