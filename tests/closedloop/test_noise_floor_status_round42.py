"""A loop at its noise floor above a nil turbulence did not diverge (round 42 PART b, B29 / B47).

docs/ADVERSARIAL.md, "Round 42 PART b, issue 27": ``closedloop run`` of kaos with one
layer of D/r0 = 1e-6 and WFS noise 0.01 (0.05) said "loop diverged: the residual at the
end (0.000671 rad^2, field mean) is 8175483.1 times the open-loop level (8.21e-11
rad^2)", while the residual was flat from the first command on at the noise floor the
budget predicted (noise term 0.00063 against 0.00065 measured).

Reference: construction, outside the code. The residual history is built by hand: frame
0 at 8.2e-11 rad^2 (the turbulence), then a flat floor of 6.5e-4 rad^2 with 10 %
scatter (a stationary process: no growth), with commands as large as the pseudo-open
loop (a loop that acts). A divergence is a growth; a flat residual is not one. The
growth case of round 24 (2 -> 8 rad^2 in 100 frames) must still read "diverged".
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


def _result(v: np.ndarray) -> SimulationResult:
    config = SimulationConfig(
        telescope=TelescopeConfig(diameter=1.0, n_pixels=8),
        layers=(LayerConfig(altitude=0.0, d_over_r0=5.0, wind_speed=10.0),),
        dms=(DMConfig(altitude=0.0, n_modes=2),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=2, field_samples=1),),
        loop=LoopConfig(time_step=T, integration_time=T, delay=T / 2),
        field=FieldConfig(size=60.0, n_points=1))
    pol = np.random.default_rng(0).standard_normal((v.shape[0], 2))
    logs = {"dm0.pol": ModalLog(pol, rate=1 / T), "dm0.commands": ModalLog(pol, rate=1 / T)}
    return SimulationResult(config=config, seed=3, predictor="none",
                            times=(np.arange(v.shape[0]) + 1) * T,
                            directions=np.zeros((1, 2)), residual_variance=v[:, None],
                            logs=logs, elapsed=0.5, version="test")


def test_flat_noise_floor_did_not_diverge():
    rng = np.random.default_rng(1)
    floor = 6.5e-4 * (1.0 + 0.1 * rng.uniform(-1.0, 1.0, 199))
    r = _result(np.concatenate([[8.2e-11], floor]))
    assert not r.diverged, r.loop_status
    assert r.loop_status.startswith("did not close: the residual"), r.loop_status
    assert "without growing" in r.loop_status


def test_growth_still_diverged():
    r = _result(np.concatenate([[2.0], np.linspace(2.0, 8.0, 99)]))
    assert r.diverged
    assert r.loop_status.startswith("diverged: the residual at the end"), r.loop_status
