"""Figure 5 writes the flagged skill test as a note under the program's prefix (review30 P6).

Fixes 47-b made every line paper_figures writes on stderr ``<program>: <kind>: <text>``
(``paper_figures.tell``); Figure 5 turns ``evaluate``'s declined and flagged skill tests
into notes of the run. test_figure5_notes_review27.py looks for "Figure 5: evaluate: ..."
anywhere in the line, so a planted ``tell("warning", ...)`` (round 30 P6) passed.
Reference: ``tell``'s docstring (the form) and the module's comment ("a declined skill test
is a note of the run"); outside ``run_as`` the program is ``python -m paper_figures``
(``program``'s docstring; pytest is not ``paper-figures``). ``evaluate`` is stubbed (only its
warning is the test's), the predictors by ``cheap_figure5_predictors`` (tests/conftest.py);
the figure stops after the notes.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.common.quiet import warn
from modalinfo.telemetry import ModalLog


def test_the_flagged_skill_test_is_a_note_line(monkeypatch, capsys, cheap_figure5_predictors):
    import modalinfo.forecast as forecast
    from paper_figures import fig5_forecast as fig5

    class StopError(Exception):
        pass

    def evaluate(*args, **kwargs):  # the real one is not the test's: only its warning
        warn("evaluate: the Diebold-Mariano p-value of 1 predictor-horizon pair(s) may be "
             "too small: the stub", UserWarning, stacklevel=2)

    def stop(*args, **kwargs):  # the rest of the figure is not the test's
        raise StopError

    monkeypatch.setattr(forecast, "evaluate", evaluate)
    monkeypatch.setattr(fig5, "_increment_correlation", stop)
    log = ModalLog(np.random.default_rng(4).standard_normal((fig5.MIN_FRAMES, 2)),
                   rate=1000.0, modes=[2, 3], units="rad")
    with pytest.raises(StopError):
        fig5.compute(log, quick=True)
    lines = capsys.readouterr().err.splitlines()
    assert ("python -m paper_figures: note: Figure 5: evaluate: the Diebold-Mariano p-value "
            "of 1 predictor-horizon pair(s) may be too small: the stub") in lines, lines
