"""An AOT file's atmosphere outer scale reaches the log's metadata (round 43 PART b, c51/c69).

``closedloop export`` writes the layers' outer scale (``LAYERS_L0``); the reader said
"records no outer scale" and the theoretical K-L assumed Kolmogorov. References: the
``LAYERS_L0`` / ``LAYERS_WEIGHT`` images written here with ``aotpy`` alone, and the
Cn2-weighted mean of the per-layer outer scales computed here by hand (the rule the
closedloop config path documents, ``(D/r0_i)^(5/3)`` proportional to the Cn2 weight).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

aotpy = pytest.importorskip("aotpy")

from modalinfo.io import load  # noqa: E402
from modalinfo.ordering.compare import kl_geometry_assumption  # noqa: E402


def _write(path, l0, weights=(0.7, 0.3)):
    tel = aotpy.MainTelescope(uid="TEL", enclosing_diameter=0.7)
    ngs = aotpy.NaturalGuideStar(uid="NGS")
    wfs = aotpy.ShackHartmann(uid="WFS", source=ngs, n_valid_subapertures=6)
    dm = aotpy.DeformableMirror(uid="DM", telescope=tel, n_valid_actuators=40)
    t = aotpy.Time("t", timestamps=(np.arange(50) / 1000.0).tolist())
    coeffs = np.random.default_rng(0).standard_normal((50, 5))
    loop = aotpy.ControlLoop(uid="L", input_sensor=wfs, commanded_corrector=dm, time=t,
                             framerate=1000.0,
                             modal_coefficients=aotpy.Image("c", coeffs, unit="rad", time=t))
    atm = aotpy.AtmosphericParameters(
        uid="ATM", wavelength=5e-7, r0=[0.1],
        layers_relative_weight=aotpy.Image("w", np.array([weights], dtype=float)),
        layers_l0=aotpy.Image("l0", np.array([l0], dtype=float), unit="m"))
    system = aotpy.AOSystem(ao_mode="SCAO", name="T", main_telescope=tel, sources=[ngs],
                            wavefront_sensors=[wfs], wavefront_correctors=[dm], loops=[loop],
                            atmosphere_params=[atm])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system.write_to_file(str(path))
    return path


def test_one_outer_scale_is_read(tmp_path):
    log = load(_write(tmp_path / "a.fits", [20.0, 20.0]))
    assert log.metadata["outer_scale"] == 20.0
    assert kl_geometry_assumption(log) is None  # nothing assumed: the file records it


def test_different_outer_scales_take_the_weighted_mean_with_a_note(tmp_path):
    log = load(_write(tmp_path / "b.fits", [20.0, 50.0]))
    assert "outer_scale" not in log.metadata
    note = kl_geometry_assumption(log)
    mean = (0.7 * 20.0 + 0.3 * 50.0) / (0.7 + 0.3)  # 29 m
    assert note is not None and "20, 50 m" in note and f"{mean:.4g} m" in note


def test_infinite_outer_scale_is_kolmogorov_recorded(tmp_path):
    log = load(_write(tmp_path / "c.fits", [np.inf, np.inf]))
    assert "outer_scale" in log.metadata and log.metadata["outer_scale"] is None
    assert kl_geometry_assumption(log) is None
