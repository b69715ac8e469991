"""0-d arrays and NumPy scalars as the closedloop numbers checked outside validation.py.

Reference, from outside the code: a 0-d array holds one number (NumPy's
``np.array(x)[()]`` is ``x``) and ``np.float32(0.25)`` is 0.25 exactly, so each call with
them must give what the call with the Python number gives, and the stored value is the
Python float (``PhotonBudget`` and ``SolarRTC`` are frozen records); a bool, a complex
number and a string stay refused. Before (left25-api's "Left" list), these checks were
``isinstance(v, (int, float))`` or ``numbers.Real`` and refused a 0-d array (and the
``(int, float)`` ones an ``np.float32``) as "must be a number". Since left26-twins they
are ``validation.check_real`` / ``check_int``, whose refusal of a non-number is a TypeError.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from closedloop import presets
from closedloop.optics.correlating import CorrelatingSubapertures
from closedloop.optics.granulation import granulation_scene
from closedloop.optics.photon_budget import PhotonBudget
from closedloop.studies import solar
from closedloop.sweep import sweep_specs

FIELDS = ("wavelength", "bandwidth", "exposure", "throughput", "quantum_efficiency",
          "read_noise", "full_well", "fill", "brightness_temperature")


@pytest.mark.parametrize("wrap", [np.array, np.float32, np.float64])
def test_photon_budget_fields_are_stored_as_python_floats(wrap):
    plain = PhotonBudget()
    given = PhotonBudget(**{f: wrap(getattr(plain, f)) for f in FIELDS})
    for f in FIELDS:
        value = getattr(given, f)
        assert type(value) is float, f
        assert value == float(np.float32(getattr(plain, f))) if wrap is np.float32 \
            else value == getattr(plain, f)
    assert type(PhotonBudget(full_well=np.int64(30000)).full_well) is float


@pytest.mark.parametrize("bad", [np.array(True), np.array(1 + 0j), np.array("1e-3"), True])
def test_photon_budget_still_refuses_non_numbers(bad):
    with pytest.raises(TypeError, match="`exposure`"):
        PhotonBudget(exposure=bad)
    with pytest.raises(TypeError, match="`read_noise`"):
        PhotonBudget(read_noise=bad)


def test_correlating_subapertures_take_0d_arrays_and_float32():
    scene = granulation_scene(64, 0.25, seed=3, wavelength=500e-9)
    plain = CorrelatingSubapertures(scene, 0.25, 0.25, 16, 24, max_shift=3)
    given = CorrelatingSubapertures(scene, np.array(0.25), np.float32(0.25), np.array(16),
                                    np.array(24), max_shift=np.array(3),
                                    n_patches=np.array(1), blur_fwhm_arcsec=np.float32(0.0),
                                    gain_rms=np.array(0.0), offset_rms=np.array(0.0))
    for attr in ("pixel_scale_arcsec", "subaperture_diameter", "n_pupil", "field_pixels",
                 "n_patches", "max_shift"):
        assert getattr(given, attr) == getattr(plain, attr)
        assert type(getattr(given, attr)) is type(getattr(plain, attr)), attr
    with pytest.raises(TypeError, match="`pixel_scale_arcsec`"):
        CorrelatingSubapertures(scene, np.array(True), 0.25, 16, 24)
    with pytest.raises(TypeError, match="`gain_rms`"):
        CorrelatingSubapertures(scene, 0.25, 0.25, 16, 24, gain_rms=np.array("0"))


def test_solar_rtc_and_compute_time_take_0d_arrays():
    rtc = solar.SolarRTC("x", np.array(0.5e-3), np.float32(32.0))
    assert (rtc.readout, rtc.rtc_speed) == (0.5e-3, 32.0)
    assert type(rtc.readout) is float and type(rtc.rtc_speed) is float
    with pytest.raises(TypeError, match="`SolarRTC.rtc_speed`"):
        solar.SolarRTC("x", 0.5e-3, np.array(True))
    cfg = presets.get("table1-solar")
    plain = solar.solar_latency(cfg, rtc=solar.SolarRTC("x", 0.5e-3, 32.0),
                                compute_time=7.7e-3)
    assert solar.solar_latency(cfg, rtc=rtc, compute_time=np.array(7.7e-3)) == plain
    with pytest.raises(TypeError, match="`compute_time`"):
        solar.solar_latency(cfg, rtc=rtc, compute_time=np.array(1 + 0j))


def test_est_variant_takes_0d_arrays():
    plain = presets.est_mcao_variant(16, altitude_pitch=2.0)
    assert presets.est_mcao_variant(np.array(16), altitude_pitch=np.array(2.0)) == plain
    with pytest.raises(TypeError, match="`altitude_pitch`"):
        presets.est_mcao_variant(16, altitude_pitch=np.array(True))


def test_sweep_duration_takes_a_0d_array():
    plain = sweep_specs({"duration": 0.01})
    given = sweep_specs({"duration": np.array(0.01)})
    assert [dataclasses.asdict(s) if dataclasses.is_dataclass(s) else s for s in given] == \
        [dataclasses.asdict(s) if dataclasses.is_dataclass(s) else s for s in plain]
    with pytest.raises(TypeError, match="grid `duration`"):
        sweep_specs({"duration": np.array(True)})
