"""A loop with no turbulence and WFS noise sits at its noise floor; it did not diverge (fixes 42).

Round 42 PART b, B29 / B47: kaos' layout with D/r0 = 1e-6 and SH noise 0.01 (0.05) was
"diverged: the residual at the end (0.000671 rad^2) is 8175483.1 times the open-loop
level (8.21e-11 rad^2)": frame 0 holds no WFS noise, so any noise floor read as growth.
Reference: the simulated science residual itself (the science camera's variance over
the second half), which the noise floor the config implies (``result.noise_floor``, the
budget's noise term) must match within the 16 draws' sampling error and the integrator
approximation (a factor 2); test_guards' ``Amplified`` loop (turbulence amplified 4.2x)
stays "diverged".
"""

import math
import warnings

import numpy as np
import pytest

from closedloop import simulate
from closedloop.config import SimulationConfig
from closedloop.result import SimulationResult

B29 = {
    "name": "kaos", "seed": 0, "wavelength": 6.3e-07, "r0_wavelength": 5e-07,
    "dms": [{"altitude": 0.0, "n_modes": 27, "kind": "zernike"}],
    "telescope": {"diameter": 0.7, "obscuration": 0.0, "zenith_angle": 0.0, "n_pixels": 56},
    "loop": {"time_step": 0.0005, "integration_time": 0.0005, "delay": 0.0005,
             "gain": 0.4664, "leak": 0.0, "model_error": 0.3},
    "field": {"size": 10.0, "n_points": 3},
    "layers": [{"altitude": 0.0, "d_over_r0": 1e-06, "wind_speed": 5.0,
                "wind_direction": 0.0, "outer_scale": 20.0}],
    "wfss": [{"altitude": 0.0, "field_of_view": 10.0, "n_subapertures": 7, "noise": 0.01,
              "kind": "shack_hartmann", "field_samples": 3, "dm": 0}],
}


def _run(noise: float):
    d = {**B29, "wfss": [{**B29["wfss"][0], "noise": noise}]}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # "total r0 ... beyond 1 m"
        cfg = SimulationConfig.from_dict(d)
        return simulate(cfg, 0.05, progress=False)


@pytest.mark.parametrize("noise", [0.01, 0.05])  # B29, B47
def test_no_turbulence_with_noise_is_at_its_noise_floor(noise):
    r = _run(noise)
    v = r.residual_variance.mean(axis=1)
    assert v[0] < 1e-9  # no turbulence: frame 0 is (almost) flat
    measured = float(v[v.size // 2:].mean())
    assert 0.5 < measured / r.noise_floor < 2.0, (measured, r.noise_floor)
    assert not r.diverged, r.loop_status
    assert r.loop_status.startswith("closed at its noise floor"), r.loop_status


def test_noise_floor_saved_and_loaded(tmp_path):
    r = _run(0.01)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # the config's r0, validated again
        back = SimulationResult.load(r.save(tmp_path / "r.h5"))
    assert back.noise_floor == r.noise_floor and back.loop_status == r.loop_status


def test_no_noise_no_floor():
    r = _run(0.0)
    assert r.noise_floor == 0.0 and not math.isnan(r.noise_floor)
    assert np.all(np.isfinite(r.residual_variance))
