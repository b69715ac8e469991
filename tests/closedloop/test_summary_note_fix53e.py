"""The Marechal caveat in ``SimulationResult.summary()`` (fix53-e, round 53 PART a C29).

Reference (outside the code): the Marechal law ``SR = exp(-sigma^2)`` on residual
histories built here (sigma^2 = 5.0 rad^2 after closure: SR exp(-5) = 0.0067, the
0.0065 of C29; 0.2 rad^2: SR 0.82), against the 0.3 below which
tests/closedloop/test_physics.py no longer validates it as the image's Strehl. The
summary carries the caveat, and the CLI's line shows the summary's text, not its own.
"""

from __future__ import annotations

import math

import numpy as np

from closedloop.cli import _summary_line
from tests.closedloop.test_result_views import _config, _result


def test_summary_names_the_marechal_regime_failure():
    low = _result(np.r_[np.full(10, 20.0), np.full(30, 5.0)], _config())
    high = _result(np.r_[np.full(10, 20.0), np.full(30, 0.2)], _config())
    s_low, s_high = low.summary(), high.summary()
    assert math.isclose(s_low["strehl_peak_mean"], math.exp(-5.0), rel_tol=1e-12)
    assert s_low["strehl_note"].startswith("SR = exp(-sigma^2) (Marechal) is below 0.3")
    assert "no longer the image's Strehl ratio" in s_low["strehl_note"]
    assert s_high["strehl_note"] == "" and s_high["strehl_peak_mean"] > 0.3
    # the command line's line reuses the summary's caveat word for word
    assert _summary_line(low).endswith("; note: " + s_low["strehl_note"])
    assert "note" not in _summary_line(high)
