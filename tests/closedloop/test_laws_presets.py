"""Each preset's layers against the turbulence its documentation states.

References: the numbers are parsed from the text (``closedloop/presets.py``'s module and
function docstrings), not from the code that builds the layers, and combined with the
3/5 law of Kolmogorov turbulence: the layers' Fried parameters add as
``r0_tot^(-5/3) = sum_i r0_i^(-5/3)`` (Roddier 1981), so ``D/r0_tot`` is
``(sum_i (D/r0_i)^(5/3))^(3/5)`` and layer i carries the fraction
``(D/r0_i)^(5/3) / (D/r0_tot)^(5/3)`` of the turbulence (its share of C_n^2 dh). Each
layer's r0 is the documented one along the line of sight (``sec z^(-3/5)``, zenith here).
"""

from __future__ import annotations

import re

import pytest

from closedloop import presets
from closedloop.optics.geometry import Geometry

#: the module docstring with its line breaks and table padding folded to single spaces
DOC = " ".join(presets.__doc__.split())


def _d_over_r0(name):
    """Per-layer D/r0 through the geometry's r0 (the Fried parameter the loop uses)."""
    cfg = presets.get(name)
    g = Geometry(cfg)  # the geometry alone: no sensors, no reconstructor
    return cfg, [cfg.telescope.diameter / g.layer_r0(i) for i in range(len(cfg.layers))]


def _total(values):
    return sum(v ** (5.0 / 3.0) for v in values) ** 0.6


def _fractions(values):
    t = sum(v ** (5.0 / 3.0) for v in values)
    return [v ** (5.0 / 3.0) / t for v in values]


def _table1_documented():
    m = re.search(r"two Kolmogorov layers with D/r0 = (\d+(?:\.\d+)?) \(ground\) and "
                  r"(\d+(?:\.\d+)?) \(upper\)", DOC)
    assert m, "table1's layers are no longer documented in closedloop/presets.py"
    return float(m.group(1)), float(m.group(2))


@pytest.mark.parametrize("name", ["table1", "table1-wind", "table1-solar"])
def test_table1_family_layers_are_the_documented_d_over_r0(name):
    ground, upper = _table1_documented()
    cfg, d_r0 = _d_over_r0(name)
    alts = [lay.altitude for lay in cfg.layers]
    assert alts == [0.0, 10_000.0]  # "upper-layer altitude 10 km" (module docstring)
    assert d_r0 == pytest.approx([ground, upper], rel=1e-12)
    # the total by the 3/5 law: the ground layer dominates (26.14 for 26 and 2)
    assert _total(d_r0) == pytest.approx(_total([ground, upper]), rel=1e-12)
    assert cfg.r0_wavelength == pytest.approx(500e-9)  # "D/r0 wavelength 500 nm"


def test_kaos_layers_are_the_documented_seeing_and_split():
    m = re.search(r"r0 = (\d+(?:\.\d+)?) cm at 500 nm a moderate daytime r0 \(D/r0 = "
                  r"(\d+(?:\.\d+)?)\)", DOC)
    assert m, "kaos's seeing is no longer documented in closedloop/presets.py"
    r0_cm, d_r0_doc = float(m.group(1)), float(m.group(2))
    m = re.search(r"(\d+) % ground, [\d.]+ m/s; (\d+) % at the split", DOC)
    assert m, "kaos's layer split is no longer documented"
    split = [float(m.group(1)) / 100.0, float(m.group(2)) / 100.0]
    m = re.search(r"aperture D = (\d+(?:\.\d+)?) m", DOC)
    diameter = float(m.group(1))
    # the documented r0 and D/r0 agree with each other
    assert diameter / (r0_cm / 100.0) == pytest.approx(d_r0_doc, rel=1e-12)
    cfg, d_r0 = _d_over_r0("kaos")
    assert cfg.telescope.diameter == pytest.approx(diameter)
    # r0 of all layers together by the 3/5 law: 7 cm
    r0_tot = diameter / _total(d_r0)
    assert r0_tot == pytest.approx(r0_cm / 100.0, rel=1e-9)
    assert _fractions(d_r0) == pytest.approx(split, rel=1e-9)
    assert [lay.altitude for lay in cfg.layers] == [0.0, 3_000.0]  # "30 % at 3 km"
    assert all(lay.outer_scale == 20.0 for lay in cfg.layers)      # "L0 = 20 m"


def test_mcao3_layers_are_the_documented_profile():
    m = re.search(r"``mcao3`` has five layers \(Big Bear-like: (\d+) % below 500 m, (\d+) % "
                  r"at (\d+)-(\d+) km, (\d+) % near the tropopause", DOC)
    assert m, "mcao3's profile is no longer documented in closedloop/presets.py"
    low, mid, top = (float(m.group(i)) / 100.0 for i in (1, 2, 5))
    mid_lo, mid_hi = float(m.group(3)) * 1e3, float(m.group(4)) * 1e3
    t = re.search(r"total D/r0 = (\d+(?:\.\d+)?)", " ".join(presets.mcao3.__doc__.split()))
    assert t, "mcao3's total D/r0 is no longer documented in its docstring"
    total_doc = float(t.group(1))
    cfg, d_r0 = _d_over_r0("mcao3")
    assert len(cfg.layers) == 5
    assert _total(d_r0) == pytest.approx(total_doc, rel=1e-12)
    frac = _fractions(d_r0)
    alts = [lay.altitude for lay in cfg.layers]
    got_low = sum(f for f, h in zip(frac, alts, strict=True) if h <= 500.0)
    got_mid = sum(f for f, h in zip(frac, alts, strict=True) if mid_lo <= h <= mid_hi)
    got_top = sum(f for f, h in zip(frac, alts, strict=True) if h > mid_hi)
    assert [got_low, got_mid, got_top] == pytest.approx([low, mid, top], rel=1e-9)
    assert got_low + got_mid + got_top == pytest.approx(1.0, rel=1e-12)
