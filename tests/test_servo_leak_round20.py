"""The integrator's leak in the stability limit (adversarial round 20 PART a, issue 27).

Reference: numpy's roots of the characteristic polynomial of the leaky integrator
``c[k] = (1 - leak) c[k-1] + g m[k]`` with a command ``d`` whole frames late and a
whole-frame exposure, ``z**(d+1) - (1 - leak) z**d + g``: the largest stable gain found
here by bisection on the largest root modulus. Analytically 2 - leak with no delay
(single pole ``1 - leak - g``) and 1 at one frame (constant term ``g``) for any leak.
Before the fix the limit ignored the leak: a diverging loop (no delay, leak 0.5, gain
1.8) ran, and a stable one (two frames, leak 0.5, gain 0.7) was refused with a wrong
pole modulus.
"""

from __future__ import annotations

import dataclasses as dc

import numpy as np
import pytest

from closedloop import presets
from closedloop.config import SimulationConfig
from modalinfo.servo import check_stable, max_stable_gain


def _edge_by_roots(delay: int, leak: float) -> float:
    lo, hi = 0.0, 3.0
    for _ in range(60):
        g = (lo + hi) / 2
        p = np.zeros(delay + 2)
        p[0], p[1] = 1.0, -(1.0 - leak)
        p[-1] += g
        lo, hi = (g, hi) if np.max(np.abs(np.roots(p))) < 1.0 else (lo, g)
    return lo


@pytest.mark.parametrize("delay", [0, 1, 2, 3, 5])
@pytest.mark.parametrize("leak", [0.0, 0.1, 0.5, 0.9])
def test_limit_with_leak_matches_roots(delay, leak):
    assert max_stable_gain(delay, 1.0, leak=leak) == pytest.approx(
        _edge_by_roots(delay, leak), rel=1e-9)


def test_closed_forms():
    assert max_stable_gain(0, 1.0, leak=0.5) == pytest.approx(1.5, rel=1e-12)
    assert max_stable_gain(1, 1.0, leak=0.5) == pytest.approx(1.0, rel=1e-12)


def test_check_stable_uses_the_leak():
    check_stable(0.7, 2.0, 1.0, leak=0.5)  # stable: limit 0.781
    with pytest.raises(ValueError, match=r"leak=0\.5; the loop is stable for gain < 1\.5000"):
        check_stable(1.8, 0.0, 1.0, leak=0.5)
    with pytest.raises(ValueError, match="`leak` must be < 1"):
        check_stable(0.5, 1.0, 1.0, leak=1.0)


def _loop(**kw):
    k = presets.get("kaos")
    c = dc.replace(k, loop=dc.replace(k.loop, **kw))
    return SimulationConfig(**{f.name: getattr(c, f.name) for f in dc.fields(c)})


def test_config_refuses_a_leaky_loop_past_its_limit_and_accepts_a_stable_one():
    with pytest.raises(ValueError, match=r"`loop\.gain` = 1\.8 .*loop\.leak=0\.5.*< 1\.5000"):
        _loop(delay=0.0, gain=1.8, leak=0.5)
    cfg = _loop(delay=0.001, gain=0.7, leak=0.5)  # two frames: stable below 0.781
    assert cfg.loop.gain == 0.7
