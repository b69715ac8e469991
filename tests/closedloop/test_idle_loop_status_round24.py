"""A loop whose commands do not act did not close; it did not diverge (round 24 a, K05).

Reference: construction, outside the code. ``simulate`` with ``loop.gain = 1e-6`` left a
residual equal to the open-loop run's frame by frame (largest relative difference
1.2e-3, one layer D/r0 = 10 at 20 m/s, seed 1, 1 s), yet ``loop_status`` said
"diverged: ... 3.5 times the open-loop level", because the level is frame 0 alone and
the turbulence of an infinite outer scale wandered 3.5x. Here the residual history of
test_result_views' growth case (2 rad^2 at frame 0, rising to a last-quarter mean of
7.27) comes with modal logs built by hand: commands at 1e-3 of the pseudo-open loop
(an idle loop: the residual is the turbulence) must read "did not close", and commands
as large as the pseudo-open loop (a loop that acts and amplifies) still "diverged".
"""

from __future__ import annotations

import numpy as np

from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.result import SimulationResult
from modalinfo.telemetry import ModalLog

T = 1e-3


def _result(command_scale: float) -> SimulationResult:
    config = SimulationConfig(
        telescope=TelescopeConfig(diameter=1.0, n_pixels=8),
        layers=(LayerConfig(altitude=0.0, d_over_r0=5.0, wind_speed=10.0),),
        dms=(DMConfig(altitude=0.0, n_modes=2),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=2, field_samples=1),),
        loop=LoopConfig(time_step=T, integration_time=T, delay=T / 2),
        field=FieldConfig(size=60.0, n_points=1))
    v = np.concatenate([[2.0], np.linspace(2.0, 8.0, 99)])[:, None]
    pol = np.random.default_rng(0).standard_normal((v.shape[0], 2))
    logs = {"dm0.pol": ModalLog(pol, rate=1 / T),
            "dm0.commands": ModalLog(command_scale * pol, rate=1 / T)}
    return SimulationResult(config=config, seed=3, predictor="none",
                            times=(np.arange(v.shape[0]) + 1) * T,
                            directions=np.zeros((1, 2)), residual_variance=v, logs=logs,
                            elapsed=0.5, version="test")


def test_idle_commands_did_not_close():
    r = _result(1e-3)
    assert not r.diverged and not r.closed
    assert r.loop_status.startswith("did not close: the commands stay at 0.001 of the "
                                    "pseudo-open-loop turbulence"), r.loop_status


def test_acting_commands_still_diverged():
    r = _result(1.0)
    assert r.diverged
    assert r.loop_status == ("diverged: the residual at the end (7.27 rad^2, field mean) is "
                             "3.6 times the open-loop level (2 rad^2)")
