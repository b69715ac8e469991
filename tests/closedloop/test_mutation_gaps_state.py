"""closedloop.state.LoopState: the maps it writes, on a plane with and without turbulence.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/state.py"). Reference, from
outside the code under test: the definition in the module docstring, rebuilt here with
numpy — a plane's residual is the sum of its layers' phase screens (``Layer.phase()``,
zero where no layer sits) minus the surface ``B c`` of each DM conjugated to it, scattered
onto the DM disc's pixels; the maps are written into the arrays given (the science
camera's views), and the clock is the atmosphere's.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from closedloop import presets
from closedloop.config import FieldConfig
from closedloop.model import LoopModel
from closedloop.state import LoopState

from .conftest import shrunk


@pytest.fixture(scope="module")
def model():
    """table1 made small, its high layer removed: the 10-km DM's plane has no turbulence."""
    c = presets.get("table1")
    c = c.replace(layers=(dataclasses.replace(c.layers[0], d_over_r0=10.0),))
    return LoopModel(shrunk(c, (9, 6), n_pixels=24, n_subapertures=6, noise=0.0, kind="ideal",
                            field=FieldConfig(size=60.0, n_points=1)))


def _reference(model, atm, command):
    out = []
    for plane in model.geometry.planes:
        ref = np.zeros((plane.n, plane.n))
        for li in plane.layers:
            ref += atm.layers[li].phase()
        for d in plane.dms:
            dm = model.dms[d]
            ref.ravel()[dm.pixels] -= dm.shapes @ command[model.mode_slices[d]]
        out.append(ref)
    return out


def test_maps_are_written_into_the_given_arrays(model):
    planes = model.geometry.planes
    assert [p.layers for p in planes] == [(0,), ()]  # one plane without a layer
    maps = [np.full((p.n, p.n), 7.0) for p in planes]  # garbage to overwrite
    atm = model.atmosphere(1, 0.02)
    state = LoopState(model, atm, maps)
    assert state.maps is maps
    state.evolve_until(0.005)
    assert state.t == atm.t == 0.005
    out = state.forward()
    assert out is maps and all(a is b for a, b in zip(out, maps, strict=True))
    for a, b in zip(out, _reference(model, atm, np.zeros(model.n_modes)), strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
    assert not maps[1].any()  # no layer, flat DM: exactly zero
    rng = np.random.default_rng(4)
    command = rng.standard_normal(model.n_modes) * 0.1
    state.apply(command)
    for d, dm in enumerate(model.dms):
        np.testing.assert_allclose(state.surfaces[d],
                                   dm.shapes @ command[model.mode_slices[d]], atol=1e-12)
    out = state.forward()
    for a, b in zip(out, _reference(model, atm, command), strict=True):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12)
    assert maps[1].any()  # the high DM's surface, seen on its own plane


def test_new_maps_and_turbulence_into_other_arrays(model):
    atm = model.atmosphere(2, 0.02)
    state = LoopState(model, atm)
    assert [m.shape for m in state.maps] == [(p.n, p.n) for p in model.geometry.planes]
    assert all(not m.any() and m.dtype == np.float64 for m in state.maps)
    assert state.maps[0] is not state.maps[1]
    assert [s.shape for s in state.surfaces] == [dm.pixels.shape for dm in model.dms]
    state.evolve_until(0.01)
    out = [np.full_like(m, -3.0) for m in state.maps]
    got = state.turbulence(out)
    assert got is out
    np.testing.assert_allclose(out[0], atm.layers[0].phase(), rtol=0, atol=1e-12)
    assert not out[1].any()
    assert not any(m.any() for m in state.maps)  # turbulence() leaves the maps alone
    state.apply(np.ones(model.n_modes))
    state.reset()
    assert state.t == 0.0 and not any(s.any() for s in state.surfaces)
