"""Review20: the idle-command rule's last quarter, and the total-r0 rule at zenith.

References, outside the code:
- numpy's RMS of hand-built command and pseudo-open-loop logs over the last quarter of
  the run (frames 75-99 of 100), the window ``loop_status``'s documentation names:
  commands that act for three quarters and then stop (1e-3 of the POL) leave an idle
  loop at the end ("did not close"), whatever they did before.
- site surveys quote r0 at zenith (Roddier 1981, sec. 3.5; the line-of-sight r0 is
  r0 cos(z)^(3/5)): a profile whose zenith r0 is 1.2 m at 500 nm is beyond the 1 m rule
  at any zenith angle, though its line-of-sight r0 at 60 deg is 1.2 x 2^-0.6 = 0.79 m.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from closedloop.presets import get

from .test_idle_loop_status_round24 import _result


def test_commands_that_stop_acting_in_the_last_quarter_read_idle():
    r = _result(1.0)
    n = r.residual_variance.shape[0]
    pol = r.logs["dm0.pol"].coeffs
    scale = np.where(np.arange(n) < n - n // 4, 1.0, 1e-3)[:, None]
    r.logs["dm0.commands"] = type(r.logs["dm0.pol"])(scale * pol, rate=1000.0)
    last = slice(n - n // 4, n)
    share = np.sqrt(np.sum(r.logs["dm0.commands"].coeffs[last] ** 2) / np.sum(pol[last] ** 2))
    assert share == pytest.approx(1e-3)
    assert not r.diverged and not r.closed
    assert r.loop_status.startswith("did not close: the commands stay at 0.001 of the "
                                    "pseudo-open-loop turbulence"), r.loop_status


def _at_zenith_angle(r0_total: float, zenith_angle: float):
    """table1 at ``zenith_angle`` [deg], its layers scaled to a zenith total r0 [m]."""
    cfg = get("table1")
    cfg = dataclasses.replace(cfg, telescope=dataclasses.replace(cfg.telescope,
                                                                 zenith_angle=zenith_angle))
    d = cfg.telescope.diameter
    weights = [layer.d_over_r0 ** (5 / 3) for layer in cfg.layers]
    scale = (d / r0_total) ** (5 / 3) / sum(weights)
    layers = tuple(dataclasses.replace(layer, d_over_r0=(w * scale) ** 0.6)
                   for layer, w in zip(cfg.layers, weights, strict=True))
    return dataclasses.replace(cfg, layers=layers)


def test_total_r0_rule_reads_the_zenith_r0_not_the_line_of_sight():
    assert 1.2 * 2.0 ** -0.6 < 1.0  # the line-of-sight r0 at 60 deg would pass
    with pytest.warns(UserWarning, match=r"`total r0 .*` = 1\.2 m is beyond 1 m at 500 nm"):
        cfg = _at_zenith_angle(1.2, 60.0)
    assert cfg.telescope.diameter / cfg.d_over_r0 == pytest.approx(1.2)
