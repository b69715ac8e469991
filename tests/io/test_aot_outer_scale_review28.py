"""An AOT file's ``LAYERS_L0`` read only where the docstring promises (review28, round 28).

``modalinfo.io.aot._atmosphere_outer_scale`` promises: the FIRST atmosphere's layers;
nothing without positive outer scales; nothing for Cn2 weights that are not weights
(negative). Planted bugs R28-A1 (a zero outer scale read as one), R28-A2 (a negative
weight accepted), R28-A3 (the last atmosphere read) escaped ``test_aot_outer_scale.py``.
References: the ``LAYERS_L0`` / ``LAYERS_WEIGHT`` images written here with ``aotpy``
alone and the reader's docstring.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

aotpy = pytest.importorskip("aotpy")

from modalinfo.io import load  # noqa: E402


def _write(path, atmospheres):
    tel = aotpy.MainTelescope(uid="TEL", enclosing_diameter=0.7)
    ngs = aotpy.NaturalGuideStar(uid="NGS")
    wfs = aotpy.ShackHartmann(uid="WFS", source=ngs, n_valid_subapertures=6)
    dm = aotpy.DeformableMirror(uid="DM", telescope=tel, n_valid_actuators=40)
    t = aotpy.Time("t", timestamps=(np.arange(50) / 1000.0).tolist())
    coeffs = np.random.default_rng(0).standard_normal((50, 5))
    loop = aotpy.ControlLoop(uid="L", input_sensor=wfs, commanded_corrector=dm, time=t,
                             framerate=1000.0,
                             modal_coefficients=aotpy.Image("c", coeffs, unit="rad", time=t))
    atms = [aotpy.AtmosphericParameters(
        uid=f"ATM{i}", wavelength=5e-7, r0=[0.1],
        layers_relative_weight=aotpy.Image(f"w{i}", np.array([w], dtype=float)),
        layers_l0=aotpy.Image(f"l0{i}", np.array([l0], dtype=float), unit="m"))
        for i, (l0, w) in enumerate(atmospheres)]
    system = aotpy.AOSystem(ao_mode="SCAO", name="T", main_telescope=tel, sources=[ngs],
                            wavefront_sensors=[wfs], wavefront_correctors=[dm], loops=[loop],
                            atmosphere_params=atms)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system.write_to_file(str(path))
    return path


def test_a_zero_outer_scale_is_not_recorded(tmp_path):
    """R28-A1: 0 m is no outer scale (the rule: positive rows only)."""
    log = load(_write(tmp_path / "z.fits", [([0.0, 0.0], (0.7, 0.3))]))
    assert "outer_scale" not in log.metadata
    assert "atmosphere_layers" not in log.metadata


def test_a_negative_cn2_weight_is_not_recorded(tmp_path):
    """R28-A2: weights (-0.5, 1.5) sum to 1 but are no Cn2 profile."""
    log = load(_write(tmp_path / "n.fits", [([20.0, 50.0], (-0.5, 1.5))]))
    assert "atmosphere_layers" not in log.metadata
    assert "outer_scale" not in log.metadata


def test_the_first_atmosphere_is_read(tmp_path):
    """R28-A3: of two atmospheres (20 m, then 50 m), the first one's outer scale."""
    log = load(_write(tmp_path / "f.fits", [([20.0, 20.0], (0.7, 0.3)),
                                            ([50.0, 50.0], (0.7, 0.3))]))
    assert log.metadata["outer_scale"] == 20.0
