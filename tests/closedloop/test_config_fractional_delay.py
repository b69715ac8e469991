"""The config's gain-stability rule at fractional delays, against hand-derived polynomials.

Reference: the closed-loop characteristic polynomial written out by hand for each case
and its roots taken by ``numpy.roots`` (Jury's criterion gives the same limits in closed
form). Frame ``k`` integrates over its whole period ``[-1, 0]`` (frames, relative to its
end); the command computed from it is applied ``delta`` frames after the end and held one
frame (Madec 1999, ch. 6). The mirror seen by frame ``k`` is then a mix of two commands,
weighted by the share of the exposure each is applied:

- ``delta = 0.25``: ``W(z) = 0.75 z^-1 + 0.25 z^-2``, so with the integrator
  ``1 - z^-1 + g W = 0``: ``z^2 + (0.75 g - 1) z + 0.25 g`` (Jury: stable for g < 4);
- ``delta = 1.5``: ``W(z) = 0.5 z^-2 + 0.5 z^-3``: ``z^3 - z^2 + 0.5 g z + 0.5 g``
  (stable for g < 2 (sqrt(2) - 1) = 0.828);
- ``delta = 2.5``: ``W(z) = 0.5 z^-3 + 0.5 z^-4``: ``z^4 - z^3 + 0.5 g z + 0.5 g``.

A loop config must accept a gain 2 % below the limit and refuse one 2 % above it. A rule
that rounded the delay to whole frames (limits 2, 1 and 2 sin(pi / 10) = 0.618) fails
each case.
"""

import dataclasses

import numpy as np
import pytest

from closedloop import presets
from closedloop.config import LoopConfig

# delay [frames] -> characteristic polynomial in z (highest power first) as a function of g
_POLYS = {
    0.25: lambda g: [1.0, 0.75 * g - 1.0, 0.25 * g],
    1.5: lambda g: [1.0, -1.0, 0.5 * g, 0.5 * g],
    2.5: lambda g: [1.0, -1.0, 0.0, 0.5 * g, 0.5 * g],
}


def _limit(poly) -> float:
    """Largest gain with every root inside the unit circle (bisection on the roots)."""
    lo, hi = 1e-6, 8.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if np.max(np.abs(np.roots(poly(mid)))) < 1.0:
            lo = mid
        else:
            hi = mid
    return lo


def test_the_hand_limits_are_the_closed_forms():
    # the polynomials' own check: Jury's closed forms for the two short ones
    assert _limit(_POLYS[0.25]) == pytest.approx(4.0, rel=1e-9)
    assert _limit(_POLYS[1.5]) == pytest.approx(2.0 * (np.sqrt(2.0) - 1.0), rel=1e-9)


@pytest.mark.parametrize("delay_frames", sorted(_POLYS))
def test_a_config_refuses_a_gain_just_above_the_fractional_delay_limit(delay_frames):
    limit = _limit(_POLYS[delay_frames])
    base = presets.table1()
    step = base.loop.time_step

    def config(gain):
        loop = LoopConfig(time_step=step, integration_time=step, delay=delay_frames * step,
                          gain=gain)
        return dataclasses.replace(base, loop=loop)

    assert config(0.98 * limit).loop.gain == 0.98 * limit
    with pytest.raises(ValueError, match="loop.gain"):
        config(1.02 * limit)
