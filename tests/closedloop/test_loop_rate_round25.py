"""Adversarial round 25 PART b, P08-P10: a closed loop's time step inside the WFS rates.

Reference: the frame rates of wavefront sensors, 1 Hz - 100 kHz
(``modalinfo.common.validation.WFS_RATE_RANGE``, the bound a log's ``rate`` is warned
on): a time step of 1000 s (0.001 Hz) was accepted by the TOML route and the Python API
alike. Both routes now refuse it with one sentence; the edges 10 us and 1 s are accepted.
"""

from __future__ import annotations

import dataclasses

import pytest

from closedloop.config import load_config, save_config
from closedloop.presets import get


def _with_step(step: float):
    cfg = get("table1")
    loop = dataclasses.replace(cfg.loop, time_step=step, integration_time=step, delay=0.0)
    layers = tuple(dataclasses.replace(layer, wind_speed=0.0) for layer in cfg.layers)
    return dataclasses.replace(cfg, loop=loop, layers=layers)


@pytest.mark.parametrize("step", [1000.0, 1.001, 0.99e-5])
def test_a_loop_outside_the_sensor_rates_is_refused_on_every_route(step, tmp_path):
    with pytest.raises(ValueError, match=r"`loop.time_step` must be in 1e-05 - 1 s "
                                         r"\(loop rates of 1 Hz - 100 kHz"):
        _with_step(step)
    path = tmp_path / "c.toml"
    text = save_config(_with_step(1.0), path).read_text()
    path.write_text(text.replace("time_step = 1.0", f"time_step = {step!r}").replace(
        "integration_time = 1.0", f"integration_time = {step!r}"))
    with pytest.raises(ValueError, match=r"`loop.time_step` must be in 1e-05 - 1 s"):
        load_config(path)


@pytest.mark.parametrize("step", [1.0, 1e-5, 1e-3])
def test_the_edges_are_accepted(step):
    assert _with_step(step).loop.time_step == step
