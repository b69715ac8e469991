"""The wrapping-screen warning says what a wrap does to the statistics (round 23 PART a, c7).

Reference: a simulator run measured in round 23 (one Kolmogorov layer, D/r0 = 8, 30 m/s,
8 s on a 4096-pixel screen covering 1.68 s): Noll's tip variance 0.448 (D/r0)^(5/3) =
14.3 rad^2 held before the first wrap (15.7) and was 778 rad^2 after it (focus 67 vs
0.81), because the low-order step at each wrap crosses the pupil. The warning must name
the time up to which statistics hold and the remedies (finite ``outer_scale``, shorter
duration, larger ``max_screen_pixels``), not only "a step".
"""

from __future__ import annotations

import pytest

from closedloop.optics.atmosphere import AtmosphericLayer


def test_wrap_warning_names_the_valid_time_and_remedies():
    with pytest.warns(RuntimeWarning, match="wraps") as rec:
        layer = AtmosphericLayer(32, 0.0625, 0.1, velocity=(70.0, 0.0), duration_hint=10.0,
                                 max_screen_pixels=256, seed=0)
    text = " ".join(str(w.message) for w in rec)
    assert f"right up to {layer.covered_time:.3g} s only" in text
    assert "outer_scale" in text and "max_screen_pixels" in text
