"""The theoretical K-L of a closedloop log uses the simulator's recorded geometry.

Issue 27, left27-geometry item 1. ``data/kaos_closedloop.npz`` records its outer scale
(20 m, every layer) in ``metadata["config"]["layers"][*]["outer_scale"]`` and its pupil
as ``metadata["dm_diameter_m"]`` (0.7 m); ``basis_for_log("kl-theory", log)`` read only
``metadata["diameter"/"outer_scale"]`` and ``["generator"]`` and built a Kolmogorov K-L
on a 1 m pupil. References, outside the function: the log's own config (read here from
its metadata by hand), closedloop's rule that a layer without ``outer_scale`` is
Kolmogorov (``closedloop.config.LayerConfig``'s default, left out of ``to_dict``), the
variance weights ``(D/r0)^(5/3)`` (Kolmogorov: a layer's phase variance scales with
``(D/r0)^(5/3)``, Noll 1976) computed here, and ``KLBasis.from_turbulence`` built with
the geometry given explicitly.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from modalinfo.bases import KLBasis, Pupil
from modalinfo.io import load
from modalinfo.ordering.compare import (
    KLGeometryWarning,
    basis_for_log,
    kl_geometry_assumption,
)
from modalinfo.telemetry.log import ModalLog

DATA = Path(__file__).resolve().parents[2] / "data"


def _silent_kl(log):
    with warnings.catch_warnings():
        warnings.simplefilter("error", KLGeometryWarning)
        return basis_for_log("kl-theory", log, n_pixels=32)


def _explicit(log, diameter, outer_scale):
    modes = [int(m) for m in log.modes]
    return KLBasis.from_turbulence(Pupil(32, diameter=diameter), len(modes),
                                   outer_scale=outer_scale, zernike_modes=modes)


def _same(basis, ref):
    np.testing.assert_allclose(basis.variances, ref.variances, rtol=1e-12)
    np.testing.assert_allclose(np.abs(basis.zernike_from_kl), np.abs(ref.zernike_from_kl),
                               rtol=0, atol=1e-12)


def _config_log(layers, dm_diameter=0.7) -> ModalLog:
    coeffs = np.random.default_rng(27).standard_normal((200, 5)) * 0.01
    config = {"name": "t", "telescope": {"diameter": 1.5}, "layers": layers}
    meta = {"source": "closedloop", "config": config}
    if dm_diameter is not None:
        meta["dm_diameter_m"] = dm_diameter
    return ModalLog(coeffs, rate=1000.0, modes=[2, 3, 4, 5, 6], units="rad", metadata=meta)


def test_shipped_closedloop_log_uses_its_config():
    log = load(DATA / "kaos_closedloop.npz")
    config = log.metadata["config"]
    (outer,) = {layer["outer_scale"] for layer in config["layers"]}
    diameter = log.metadata["dm_diameter_m"]
    assert (outer, diameter) == (20.0, 0.7)  # what the file records
    assert kl_geometry_assumption(log) is None
    basis = _silent_kl(log)  # warned "no outer scale" (Kolmogorov) before
    ref = _explicit(log, diameter, outer)
    np.testing.assert_allclose(basis.pupil.diameter, diameter)
    _same(basis, ref)


def test_kolmogorov_layers_are_recorded_not_assumed():
    # closedloop leaves an infinite outer scale out of its config: recorded, not absent
    log = _config_log([{"altitude": 0.0, "d_over_r0": 5.0, "wind_speed": 5.0}])
    assert kl_geometry_assumption(log) is None
    basis = _silent_kl(log)
    ref = _explicit(log, 0.7, math.inf)
    _same(basis, ref)


def test_telescope_diameter_when_no_dm_diameter():
    log = _config_log([{"altitude": 0.0, "d_over_r0": 5.0, "wind_speed": 5.0,
                        "outer_scale": 30.0}], dm_diameter=None)
    basis = _silent_kl(log)
    assert basis.pupil.diameter == 1.5


def test_layers_of_different_outer_scales_use_the_variance_weighted_one():
    d_r0 = (8.0, 4.0)
    log = _config_log([{"altitude": 0.0, "d_over_r0": d_r0[0], "wind_speed": 5.0,
                        "outer_scale": 20.0},
                       {"altitude": 3000.0, "d_over_r0": d_r0[1], "wind_speed": 9.0,
                        "outer_scale": 50.0}])
    w = [x ** (5 / 3) for x in d_r0]
    expected = (20.0 * w[0] + 50.0 * w[1]) / (w[0] + w[1])  # 27.19 m
    note = kl_geometry_assumption(log, option="--outer-scale M")
    assert note is not None and "20, 50 m" in note and f"{expected:.4g} m" in note
    assert note.endswith("--outer-scale M sets one")
    with pytest.warns(KLGeometryWarning, match="weighted"):
        basis = basis_for_log("kl-theory", log, n_pixels=32)
    ref = _explicit(log, 0.7, expected)
    _same(basis, ref)
    # the outer scale given explicitly: nothing assumed, nothing said
    assert kl_geometry_assumption(log, 20.0) is None
    with warnings.catch_warnings():
        warnings.simplefilter("error", KLGeometryWarning)
        basis_for_log("kl-theory", log, n_pixels=32, outer_scale=20.0)


def test_a_kolmogorov_layer_among_finite_ones_makes_the_mean_infinite():
    log = _config_log([{"altitude": 0.0, "d_over_r0": 8.0, "wind_speed": 5.0,
                        "outer_scale": 20.0},
                       {"altitude": 3000.0, "d_over_r0": 4.0, "wind_speed": 9.0}])
    note = kl_geometry_assumption(log)
    assert note is not None and "20, inf m" in note and "inf m" in note
