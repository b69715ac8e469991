"""Adversarial round 25 PART b, P04 / P05: a profile's total r0 under modalinfo's r0 rule.

Reference: site surveys give r0 = 2-20 cm at 500 nm (0.3 m on an exceptional night), the
range ``modalinfo.common.validation.check_r0`` encodes (refused below 1 mm, warned above
1 m). The total is ``D / (sum_l (D/r0_l)**(5/3))**(3/5)`` (Fried 1966; Roddier 1981),
computed here by hand. Layers giving a total of 2 m or 16 m at 500 nm ran without a
word; table1's own total (15 cm, its weak 10-km layer alone 2 m) stays silent.
"""

from __future__ import annotations

import dataclasses
import warnings

import pytest

from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.presets import get, names


def _with_total(r0_total: float, r0_wavelength: float = 500e-9):
    cfg = get("table1")
    d = cfg.telescope.diameter
    weights = [layer.d_over_r0 ** (5 / 3) for layer in cfg.layers]
    scale = (d / r0_total) ** (5 / 3) / sum(weights)
    layers = tuple(dataclasses.replace(layer, d_over_r0=(w * scale) ** 0.6)
                   for layer, w in zip(cfg.layers, weights, strict=True))
    return dataclasses.replace(cfg, layers=layers, r0_wavelength=r0_wavelength)


@pytest.mark.parametrize("r0_total", [2.0, 16.0])
def test_an_implausibly_large_total_r0_warns_once(r0_total):
    with pytest.warns(UserWarning, match=r"`total r0 .*` = .* beyond 1 m at 500 nm") as rec:
        cfg = _with_total(r0_total)
    assert len([w for w in rec if "total r0" in str(w.message)]) == 1
    assert cfg.telescope.diameter / cfg.d_over_r0 == pytest.approx(r0_total)


def test_a_total_r0_below_1_mm_is_refused():
    # on table1's 6.25 cm pixels the sampling rule (r0 >= one pixel) refuses first; on a
    # 5 cm pupil of 128 pixels (0.39 mm) a total r0 of 0.8 mm meets the r0 rule itself
    def small(r0_total):
        return SimulationConfig(
            telescope=TelescopeConfig(diameter=0.05, n_pixels=128),
            layers=(LayerConfig(altitude=0.0, d_over_r0=0.05 / r0_total, wind_speed=0.0),),
            dms=(DMConfig(altitude=0.0, n_modes=2),),
            wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=2,
                            field_samples=1),),
            field=FieldConfig(size=0.0, n_points=1))

    small(1.01e-3)
    with pytest.raises(ValueError, match=r"`total r0 .*` must be >= 0.001 m at 500 nm"):
        small(0.8e-3)
    with pytest.raises(ValueError, match=r"`layers\[\*\].d_over_r0` must be such that r0"):
        _with_total(0.5e-3)


def test_the_rule_is_at_500_nm():
    # r0 scales as lambda**(6/5): 1.5 m quoted at 1 um is 1.5 * 0.5**1.2 = 0.65 m at 500 nm
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _with_total(1.5, r0_wavelength=1e-6)
    with pytest.warns(UserWarning, match="at 500 nm"):
        _with_total(2.5, r0_wavelength=1e-6)  # 1.09 m at 500 nm


@pytest.mark.parametrize("name", names())
def test_every_preset_is_silent(name):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cfg = get(name)
    assert 0.01 < cfg.telescope.diameter / cfg.d_over_r0 < 0.3
