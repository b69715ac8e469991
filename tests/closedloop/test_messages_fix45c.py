"""Refusals of the loop that state the rule as applied (fixes 45-c, round 45 PART b).

References, from outside the code: the analytic integrator limit 2 sin(pi / (2 (2n - 1)))
= 1 for n = 1 frame of delay (the limit ``max_stable_gain`` computes to its stated 1e-12
relative accuracy); the refused gains one ulp (``numpy.nextafter``) and 5e-13 below it;
Python's ``round`` of duration / time_step, the run's whole frames, by hand.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from closedloop import simulate
from modalinfo.servo import check_stable

from .conftest import small


@pytest.mark.parametrize("gain", [float(np.nextafter(1.0, 0.0)), 1.0 - 5e-13])
def test_gain_bound_is_printed_below_the_refused_gain(gain):
    # T90 / T104: "stable for gain < 1.0000" refused 1 - 1 ulp, a gain below the printed
    # bound; the bound applied is the limit 1 less its 1e-12 accuracy
    with pytest.raises(ValueError, match="makes the loop unstable") as exc:
        check_stable(gain, 1.0, 1.0)
    shown = float(re.search(r"stable for gain < ([0-9.]+)", str(exc.value)).group(1))
    assert shown <= gain  # the refused gain is visibly on the wrong side
    assert 1.0 - 2e-12 <= shown < 1.0  # and the bound is the analytic limit's, to 1e-12


def test_gain_far_from_the_limit_keeps_four_decimals():
    with pytest.raises(ValueError, match=r"stable for gain < 1\.0000\.$"):
        check_stable(1.5, 1.0, 1.0)  # 1.5 >= 1.0000 visibly: round 3's form kept


def test_duration_refusal_states_the_whole_frames_applied():
    # T106: 0.0020001 s is longer than time_step + delay = 0.002 s, but rounds to
    # round(2.0001) = 2 frames of 0.001 s; 3 frames (0.003 s) are the fewest that close
    cfg = small(delay=1e-3)
    with pytest.raises(ValueError, match=r"got 0\.0020001 s, which rounds to 2 frame\(s\) "
                                         r"of loop\.time_step = 0\.001 s \(0\.002 s\): give "
                                         r"3 frames or more \(0\.003 s\)"):
        simulate(cfg, 0.0020001, progress=False)
