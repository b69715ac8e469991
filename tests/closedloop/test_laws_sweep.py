"""A sweep row's "on-axis" budget is the run's budget at the field point (0, 0).

Reference: the same run made directly (``closedloop.simulate``, same config and seed:
same bits) and its budget read at the direction whose coordinates are exactly (0, 0),
found here from the directions; the config is an MCAO one whose budget varies over the
field (a high layer seen off axis by the ground DM, anisoplanatism), so that any other
direction gives other numbers (checked). The grid goes through ``sweep_specs`` and
``run_one`` (the task a worker runs), without a cluster.
"""

from __future__ import annotations

import numpy as np
import pytest

from closedloop import simulate
from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
    save_config,
)
from closedloop.sweep import run_one, sweep_specs

TERMS = ("fitting", "aliasing", "temporal", "noise", "measured")


def _config():
    return SimulationConfig(
        name="sweep-laws",
        telescope=TelescopeConfig(diameter=2.0, n_pixels=24),
        layers=(LayerConfig(altitude=0.0, d_over_r0=6.0, wind_speed=5.0),
                LayerConfig(altitude=8000.0, d_over_r0=4.0, wind_speed=15.0,
                            wind_direction=90.0)),
        dms=(DMConfig(altitude=0.0, n_modes=14), DMConfig(altitude=8000.0, n_modes=9)),
        wfss=(WFSConfig(altitude=0.0, field_of_view=30.0, n_subapertures=6, noise=0.01,
                        dm=0),
              WFSConfig(altitude=8000.0, field_of_view=10.0, n_subapertures=6, noise=0.01,
                        dm=1)),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=0.5e-3, gain=0.4),
        field=FieldConfig(size=40.0, n_points=3), wavelength=630e-9, r0_wavelength=500e-9,
        seed=0)


@pytest.fixture(scope="module")
def row_and_run(tmp_path_factory):
    cfg = _config()
    path = tmp_path_factory.mktemp("sweep") / "base.toml"
    save_config(cfg, path)
    grid = {"config": str(path), "duration": 0.04, "seeds": [3], "budget_every": 2}
    (spec,) = sweep_specs(grid)
    row = run_one(dict(spec.payload))
    run = simulate(cfg, 0.04, seed=3, progress=False, budget_every=2)
    return row, run


def test_on_axis_row_is_the_budget_at_the_origin(row_and_run):
    row, run = row_and_run
    b = run.budget
    origin = np.flatnonzero(np.all(b.directions == 0.0, axis=1))
    assert origin.size == 1
    k = int(origin[0])
    for term in TERMS:
        assert row[f"budget_{term}_on_axis"] == float(getattr(b, term)[k]), term


def test_the_field_point_matters(row_and_run):
    # the test can fail: every other direction has a different budget
    row, run = row_and_run
    b = run.budget
    k = int(np.flatnonzero(np.all(b.directions == 0.0, axis=1))[0])
    others = [i for i in range(len(b.directions)) if i != k]
    for i in others:
        assert abs(b.fitting[i] - b.fitting[k]) > 0.01 * b.fitting[k]
        assert b.measured[i] != row["budget_measured_on_axis"]
