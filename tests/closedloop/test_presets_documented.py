"""Each preset holds the numbers its documentation gives, and only those changes.

References (outside the code): the tables of ``closedloop.presets``' module docstring
and the paper's Table 1 (Stangalini et al.: D = 4 m, 1 ms step and exposure, 0.5 ms
delay, D/r0 = 26 and 2, winds 7 and 70 m/s), typed here; the seeing written as r0
(15.4 cm for table1, 7 cm for kaos) and as turbulence fractions (kaos 70/30 %, mcao3
"60 % below 500 m, 35 % at 1-7 km, 5 % near the tropopause") checked through the
Kolmogorov law ``(D/r0)^(5/3)`` additive over layers; the kaos gain against
``modalinfo.servo.gain_for_bandwidth`` (130 Hz 0 dB rejection bandwidth); the variants
(``table1-wind``, ``table1-solar``) against ``table1`` with only their documented
changes.
"""

from __future__ import annotations

import dataclasses
import math

import pytest

from closedloop import presets
from closedloop.config import LayerConfig, SimulationConfig
from modalinfo.servo import gain_for_bandwidth


def _strengths(config: SimulationConfig) -> list[float]:
    """Each layer's share of the turbulence, ``(D/r0_l)^(5/3) / sum``."""
    s = [lay.d_over_r0 ** (5 / 3) for lay in config.layers]
    return [x / sum(s) for x in s]


def _layers(config):
    return [(lay.altitude, lay.wind_speed, lay.wind_direction, lay.outer_scale)
            for lay in config.layers]


def test_names_and_unknown_name():
    assert presets.names() == ["table1", "table1-wind", "table1-solar", "mcao3", "kaos",
                               "dkist-scao", "dkist-scao-5cm", "est-mcao", "est-mcao-solar"]
    for name in presets.names():
        assert presets.get(name).name == name
    with pytest.raises(ValueError, match="^`name` must be one of table1, table1-wind, "
                       "table1-solar, mcao3, kaos, dkist-scao, dkist-scao-5cm, est-mcao, "
                       "est-mcao-solar; got 'table2'"):
        presets.get("table2")


def test_table1_is_the_papers_table_with_the_documented_choices():
    c = presets.get("table1")
    t = c.telescope
    assert (t.diameter, t.obscuration, t.zenith_angle, t.n_pixels) == (4.0, 0.0, 0.0, 64)
    assert [lay.d_over_r0 for lay in c.layers] == [26.0, 2.0]
    assert _layers(c) == [(0.0, 7.0, 0.0, math.inf), (10_000.0, 70.0, 90.0, math.inf)]
    # "r0 = 15.4 cm at 500 nm: 2.5 px per r0" (the ground layer's, D / 26), pixels of 6.25 cm
    r0 = t.diameter / c.layers[0].d_over_r0
    assert t.diameter / t.n_pixels == 0.0625
    assert round(r0 * 100, 1) == 15.4 and round(r0 / (t.diameter / t.n_pixels), 1) == 2.5
    assert [(d.altitude, d.n_modes, d.kind, d.diameter) for d in c.dms] == [
        (0.0, 119, "zernike", None), (10_000.0, 65, "zernike", None)]  # Z2-Z120, Z2-Z66
    assert [(w.altitude, w.field_of_view, w.n_subapertures, w.noise, w.kind, w.dm)
            for w in c.wfss] == [(0.0, 60.0, 16, 0.005, "shack_hartmann", 0),
                                 (10_000.0, 20.0, 16, 0.005, "shack_hartmann", 1)]
    lp = c.loop
    assert (lp.time_step, lp.integration_time, lp.delay, lp.gain, lp.leak, lp.closed) == (
        1e-3, 1e-3, 0.5e-3, 0.5, 0.0, True)
    assert (c.field.size, c.field.n_points) == (120.0, 9)
    assert (c.wavelength, c.r0_wavelength, c.seed) == (630e-9, 500e-9, 0)


def test_table1_wind_changes_only_the_ground_wind():
    base, c = presets.get("table1"), presets.get("table1-wind")
    assert c.layers[0].wind_speed == 21.0 == 3 * base.layers[0].wind_speed
    ground = dataclasses.replace(base.layers[0], wind_speed=21.0)
    assert c == base.replace(name="table1-wind", layers=(ground, base.layers[1]))


def test_table1_solar_changes_only_the_sensors_and_the_delay():
    base, c = presets.get("table1"), presets.get("table1-solar")
    assert presets.SOLAR_RTC_DELAY == 1.0e-3 == c.loop.delay  # 1 ms, two 0.5 ms stages
    for w, b in zip(c.wfss, base.wfss, strict=True):
        assert (w.kind, w.noise, w.pixel_scale, w.signal, w.contrast, w.image_formation) == (
            "correlating", 0.0, 0.5, None, None, False)
        assert (w.altitude, w.field_of_view, w.n_subapertures, w.dm) == (
            b.altitude, b.field_of_view, b.n_subapertures, b.dm)
    assert c == base.replace(name="table1-solar", wfss=c.wfss,
                             loop=dataclasses.replace(base.loop, delay=1.0e-3))


def test_mcao3_fractions_altitudes_and_dms():
    c = presets.get("mcao3")
    share = _strengths(c)
    alts = [lay.altitude for lay in c.layers]
    assert alts == [0.0, 500.0, 4_000.0, 7_000.0, 12_000.0]
    below = sum(f for f, h in zip(share, alts, strict=True) if h <= 500.0)
    middle = sum(f for f, h in zip(share, alts, strict=True) if 1_000.0 <= h <= 7_000.0)
    assert below == pytest.approx(0.60, abs=1e-12)
    assert middle == pytest.approx(0.35, abs=1e-12)
    assert share[-1] == pytest.approx(0.05, abs=1e-12)
    assert share == pytest.approx([0.45, 0.15, 0.2, 0.15, 0.05], abs=1e-12)
    assert c.d_over_r0 == pytest.approx(26.0, rel=1e-12)  # table1's ground layer in total
    assert [lay.wind_speed for lay in c.layers] == [7.0, 10.0, 20.0, 30.0, 70.0]
    assert [lay.wind_direction for lay in c.layers] == [0.0, 30.0, 60.0, 120.0, 90.0]
    assert [(d.altitude, d.n_modes) for d in c.dms] == [(0.0, 119), (4_000.0, 65),
                                                        (10_000.0, 44)]
    assert [(w.altitude, w.field_of_view, w.n_subapertures, w.noise, w.dm) for w in c.wfss] == [
        (0.0, 60.0, 16, 0.005, 0), (4_000.0, 30.0, 16, 0.005, 1), (10_000.0, 20.0, 16, 0.005, 2)]
    base = presets.get("table1")
    assert (c.telescope, c.loop, c.field, c.wavelength, c.r0_wavelength, c.seed) == (
        base.telescope, base.loop, base.field, base.wavelength, base.r0_wavelength, base.seed)


def test_kaos_documented_values():
    c = presets.get("kaos")
    t = c.telescope
    assert (t.diameter, t.obscuration, t.zenith_angle, t.n_pixels) == (0.7, 0.0, 0.0, 56)
    # 7 x 7 subapertures of 10 cm, 8 pixels each; pixels of 1.25 cm
    (w,) = c.wfss
    assert (w.n_subapertures, w.field_of_view, w.noise, w.kind, w.dm, w.altitude) == (
        7, 10.0, 0.01, "shack_hartmann", 0, 0.0)
    assert t.diameter / w.n_subapertures == pytest.approx(0.10, rel=1e-12)
    assert t.n_pixels / w.n_subapertures == 8 and t.diameter / t.n_pixels == pytest.approx(0.0125)
    (dm,) = c.dms
    assert (dm.altitude, dm.n_modes, dm.kind) == (0.0, 27, "zernike")  # Z2-Z28
    # r0 = 7 cm at 500 nm (D/r0 = 10), 70 % on the ground, 30 % at 3 km, orthogonal winds
    assert c.d_over_r0 == pytest.approx(10.0, rel=1e-12)
    assert t.diameter / c.d_over_r0 == pytest.approx(0.07, rel=1e-12)
    assert _strengths(c) == pytest.approx([0.7, 0.3], abs=1e-12)
    assert _layers(c) == [(0.0, 5.0, 0.0, 20.0), (3_000.0, 10.0, 90.0, 20.0)]
    lp = c.loop
    assert (lp.time_step, lp.integration_time, lp.delay, lp.leak) == (0.5e-3, 0.5e-3,
                                                                      0.5e-3, 0.0)
    assert lp.gain == presets.KAOS_GAIN and presets.KAOS_BANDWIDTH == 130.0
    exact = gain_for_bandwidth(130.0, rate=2000.0, delay_frames=1.0, integration_frames=1.0)
    assert lp.gain == pytest.approx(exact, abs=5e-5)  # the 4 decimals it is written with
    assert (c.field.size, c.field.n_points, c.wavelength, c.r0_wavelength, c.seed) == (
        10.0, 3, 630e-9, 500e-9, 0)


# the replacement layers (D/r0 = 1 each, a total r0 of metres) only need to differ
@pytest.mark.filterwarnings("ignore:`total r0 .* is beyond 1 m at 500 nm:UserWarning")
def test_every_preset_is_a_fresh_object():
    # a caller changing its copy (replace) never changes the preset
    for name in presets.names():
        a = presets.get(name)
        b = a.replace(layers=(LayerConfig(altitude=0.0, d_over_r0=1.0, wind_speed=1.0),) * len(
            a.layers))
        assert presets.get(name) == a != b
