"""The compression study's gain at a measured delay where the preset's gain is unstable.

Reference: the integrator's stability limit for a whole-frame exposure and a delay of n
whole frames, g_max = 2 sin(pi / (2 (2 n + 1))) (1 at one frame, 0.618 at two, 0.445 at
three; the root-locus of z^(n+1) - z^n + g = 0 on the unit circle), by hand. Figure 6's
latency runs measure the RTC's step time; on a loaded machine a slow-RTC delay of 4.125
frames made the preset's gain 0.4664 unstable and the main job stopped (stop 48). The
gain is now scaled to keep the preset's gain margin; stable delays keep it.
"""

from __future__ import annotations

import math

import pytest

from closedloop import presets
from closedloop.studies.compression import gain_for_delay
from modalinfo.servo import check_stable


def _limit(n: int) -> float:
    return 2.0 * math.sin(math.pi / (2 * (2 * n + 1)))


def test_stable_delays_keep_the_preset_gain():
    loop = presets.get("kaos").loop
    assert loop.delay_frames == pytest.approx(1.0) and loop.integration_frames == 1.0
    for n in (1, 2):  # 0.4664 < 1, < 0.618
        new, changed = gain_for_delay(loop, n * loop.time_step)
        assert not changed and new.gain == loop.gain
        assert new.delay == pytest.approx(n * loop.time_step)


@pytest.mark.parametrize("n", [3, 4, 6])
def test_unstable_delays_keep_the_preset_gain_margin(n):
    loop = presets.get("kaos").loop
    assert loop.gain >= _limit(n)  # the preset's gain is unstable there
    new, changed = gain_for_delay(loop, n * loop.time_step)
    assert changed
    # the preset's margin g / g_max(1 frame) = g / 1 is kept at n frames
    assert new.gain == pytest.approx(loop.gain * _limit(n) / _limit(1), rel=1e-9)
    check_stable(new.gain, new.delay_frames, new.integration_frames, leak=new.leak)
