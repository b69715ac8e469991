"""closedloop's scalar checks through validation.check_real, and a config's wind rule.

Issue 27, left26-twins. References, from outside the code under test:

- a number is finite or it is not (IEEE 754): an infinite pixel scale, subaperture or
  detector noise describes no detector, so ``CorrelatingSubapertures`` must refuse
  ``inf`` as it refuses ``nan`` (before, ``not v > 0`` let ``inf`` through);
- a 0-d array and a NumPy number hold one number (``np.array(x)[()]`` is ``x``,
  ``np.float32(2.5)`` is 2.5 exactly), so ``estimate``'s ``limit`` given that way is
  that number (before, ``isinstance(limit, int | float)`` refused ``np.float32`` and
  0-d arrays), while a bool is no size;
- winds of the atmosphere: jet-stream cores blow at 30-70 m/s and rarely reach
  100 m/s (e.g. Roddier 1981; the Bufton profile peaks near 30 m/s); a config layer
  faster than 100 m/s is km/h or mph typed as m/s, refused as modalinfo's ``Layer``
  refuses it; 0 m/s (a static layer) and 100 m/s stay accepted;
- the command line's contract (README): one line on stderr, exit status 2.
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

from closedloop import presets
from closedloop import resources as res
from closedloop.cli import main
from closedloop.config import SimulationConfig
from closedloop.optics.correlating import CorrelatingSubapertures
from closedloop.optics.granulation import granulation_scene


@pytest.fixture(scope="module")
def scene():
    return granulation_scene(64, 0.25, seed=3, wavelength=500e-9)


@pytest.mark.parametrize(("kw", "name"), [
    ({"pixel_scale_arcsec": np.inf}, "pixel_scale_arcsec"),
    ({"subaperture_diameter": np.inf}, "subaperture_diameter"),
    ({"gain_rms": np.inf}, "gain_rms"),
    ({"offset_rms": np.inf}, "offset_rms"),
    ({"blur_fwhm_arcsec": np.inf}, "blur_fwhm_arcsec"),
])
def test_correlating_refuses_infinite_numbers(scene, kw, name):
    args = {"pixel_scale_arcsec": 0.25, "subaperture_diameter": 0.25} | kw
    with pytest.raises(ValueError) as exc:
        CorrelatingSubapertures(scene, args.pop("pixel_scale_arcsec"),
                                args.pop("subaperture_diameter"), 16, 24, **args)
    assert str(exc.value) == f"`{name}` must be finite; got inf."


def test_correlating_counts_refuse_floats_as_check_int_does(scene):
    with pytest.raises(TypeError, match=r"^`max_shift` must be an int; got 3.0\.$"):
        CorrelatingSubapertures(scene, 0.25, 0.25, 16, 24, max_shift=3.0)
    with pytest.raises(ValueError, match=r"^`n_pupil` must be an int >= 2; got 1\.$"):
        CorrelatingSubapertures(scene, 0.25, 0.25, 1, 24)


@pytest.mark.parametrize("wrap", [np.float32, np.array, np.uint64])
def test_memory_limit_as_a_numpy_number(wrap):
    cfg = presets.get("kaos")
    with pytest.raises(res.ResourceError):  # 1 kB: every run needs more
        res.check_resources(cfg, 0.01, limit=wrap(1000))
    assert res.check_resources(cfg, 0.01, limit=wrap(2**50)).peak_bytes > 0
    with pytest.raises(TypeError, match=r"^`memory_limit` must be a real number; got True\.$"):
        res.check_resources(cfg, 0.01, limit=np.bool_(True))


def _kaos(**layer0) -> dict:
    d = presets.get("kaos").to_dict()
    d["layers"][0].update(layer0)
    return d


@pytest.mark.parametrize("speed", [100.5, 150.0, 1e6])
def test_config_layer_faster_than_any_jet_stream_is_refused(speed):
    with pytest.raises(ValueError) as exc:
        SimulationConfig.from_dict(_kaos(wind_speed=speed))
    assert str(exc.value).startswith(
        f"`layers[0].wind_speed` must be <= 100 m/s (in m/s; jet-stream cores blow at "
        f"30-70 m/s, rarely 100); got {speed!r}")


@pytest.mark.parametrize("speed", [0.0, 0, 100.0, 35.0])
def test_config_layer_winds_of_the_atmosphere_are_kept(speed):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cfg = SimulationConfig.from_dict(_kaos(wind_speed=speed))
    assert cfg.layers[0].wind_speed == speed


def test_every_preset_is_silent_under_the_wind_rule():
    for name in presets.names():
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            cfg = presets.get(name)
        assert max(layer.wind_speed for layer in cfg.layers) <= 100.0, name


def test_the_command_line_says_the_wind_rule_in_one_line(tmp_path, capsys):
    path = tmp_path / "fast.json"
    path.write_text(json.dumps(_kaos(wind_speed=360.0)))
    assert main(["config", "--config", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert "`layers[0].wind_speed` must be <= 100 m/s" in err and "got 360.0" in err, err
