"""The loop's shape: one protocol for its parts, a WFS registry, small functions, no back doors.

References: the source itself read with ``ast`` (function lengths, who calls which
private name, which module imports which), ``typing.runtime_checkable`` for the
protocol, and independent numpy re-implementations of a loop step (each layer's checked
public ``phase()`` summed per plane, minus each DM's ``shapes @ c`` scattered on its
disc) and of the snapshot camera (a camera built for the same directions on copied maps).
"""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

import numpy as np
import pytest

import closedloop
from closedloop import presets
from closedloop.config import WFS_KINDS, DMConfig, FieldConfig, TelescopeConfig, WFSConfig
from closedloop.control.controller import Controller
from closedloop.kinds import (
    register_sensor_kind,
    sensor_kind,
    sensor_kinds,
    unregister_sensor_kind,
)
from closedloop.model import LoopModel
from closedloop.optics.science import ScienceCamera
from closedloop.optics.wfs import IDEAL, IdealSensor, ShackHartmann
from closedloop.parts import Part, Sensor, TimedPart
from closedloop.state import LoopState

PACKAGE = Path(closedloop.__file__).resolve().parent

#: function body lines (docstring excluded) that no function may reach
MAX_LINES = 90

#: functions over the limit, with the reason they may still be
EXEMPT: dict[tuple[str, str], str] = {}


def _functions():
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                yield path, node


def _body_lines(node) -> int:
    """Lines from ``def`` to the end, less the docstring's (prose is not code)."""
    n = node.end_lineno - node.lineno + 1
    first = node.body[0]
    if (isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant)
            and isinstance(first.value.value, str)):
        n -= first.end_lineno - first.lineno + 1
    return n


def test_every_function_is_short():
    long = {(p.name, f.name): _body_lines(f) for p, f in _functions()
            if _body_lines(f) >= MAX_LINES and (p.name, f.name) not in EXEMPT}
    assert not long, f"functions of {MAX_LINES}+ lines (docstring excluded): {long}"


def test_simulate_reads_in_a_page():
    (node,) = [f for p, f in _functions() if p.name == "simulation.py" and f.name == "simulate"]
    assert _body_lines(node) < 80


def test_exemptions_are_still_needed():
    lines = {(p.name, f.name): _body_lines(f) for p, f in _functions()}
    stale = [k for k in EXEMPT if lines.get(k, 0) < MAX_LINES]
    assert not stale, f"remove these exemptions, the functions are short now: {stale}"


@pytest.mark.parametrize("private, owner", [
    ("_phase_into", "atmosphere.py"),
    ("_fill_planes", None),
    ("_flat", "science.py"),
])
def test_no_private_back_doors(private, owner):
    """A private name is used only in the module that defines it (never, if it is gone)."""
    users = set()
    for path in PACKAGE.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            name = (node.attr if isinstance(node, ast.Attribute)
                    else node.id if isinstance(node, ast.Name) else None)
            if name == private:
                users.add(path.name)
    assert users <= ({owner} if owner else set()), users


def _imports(module: str) -> set[str]:
    """closedloop modules imported anywhere in ``module`` (function-level imports too)."""
    tree = ast.parse((PACKAGE / f"{module}.py").read_text())
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            if node.module.startswith("closedloop."):
                out.add(node.module.split(".")[1])
            elif node.module == "closedloop":
                out.update(a.name for a in node.names)
        elif isinstance(node, ast.Import):
            out.update(a.name.split(".")[1] for a in node.names
                       if a.name.startswith("closedloop."))
    return out


@pytest.mark.parametrize("module", ["budget", "model", "state", "parts", "wfs", "dm",
                                    "science", "atmosphere", "control"])
def test_parts_do_not_import_the_loop(module):
    """The parts, the model, the state and the budget probe sit below the loop."""
    seen, todo = set(), [module]
    while todo:
        m = todo.pop()
        if m in seen or not (PACKAGE / f"{m}.py").is_file():
            continue
        seen.add(m)
        todo.extend(_imports(m))
    assert "simulation" not in seen, sorted(seen)


@pytest.fixture(scope="module")
def model():
    """mcao3 made small, with both sensor kinds and two layers on the ground plane."""
    c = presets.get("mcao3")
    dms = tuple(DMConfig(altitude=d.altitude, n_modes=m)
                for d, m in zip(c.dms, (20, 14, 9), strict=True))
    wfss = tuple(WFSConfig(altitude=w.altitude, field_of_view=w.field_of_view, n_subapertures=8,
                           noise=w.noise if j != 1 else 0.0, dm=w.dm, field_samples=2,
                           kind="ideal" if j == 1 else "shack_hartmann")
                 for j, w in enumerate(c.wfss))
    layers = (*c.layers, dataclasses.replace(c.layers[0], wind_direction=200.0, d_over_r0=5.0))
    return LoopModel(c.replace(telescope=TelescopeConfig(diameter=4.0, n_pixels=32), dms=dms,
                               wfss=wfss, layers=layers, field=FieldConfig(size=60.0, n_points=3)))


def test_parts_follow_the_protocol(model):
    state = LoopState(model, model.atmosphere(0, 0.01))
    ctl = Controller(3, gain=0.3, leak=0.0, delay_frames=0.5, integration_frames=1.0)
    for part in (*model.dms, *model.wfss, model.science, state.atmosphere, state, ctl):
        assert isinstance(part, Part), type(part).__name__
    for part in (state.atmosphere, state):
        assert isinstance(part, TimedPart), type(part).__name__
    for wfs in model.wfss:
        assert isinstance(wfs, Sensor)
    assert any(len(p.layers) > 1 for p in model.geometry.planes)  # the summing path is tested


def test_sensor_registry(model):
    assert set(sensor_kinds()) == set(WFS_KINDS) == {"shack_hartmann", "ideal", "correlating"}
    assert sensor_kind("shack_hartmann").build is ShackHartmann
    assert sensor_kind("ideal").build is IdealSensor
    for wfs, cfg in zip(model.wfss, model.config.wfss, strict=True):
        assert type(wfs) is sensor_kind(cfg.kind).build
    with pytest.raises(TypeError, match="`kind` must be a SensorKind"):
        register_sensor_kind(IdealSensor)
    with pytest.raises(ValueError, match="`kind.name` must be a new sensor kind; "
                                         "'shack_hartmann' is registered already"):
        register_sensor_kind(dataclasses.replace(IDEAL, name="shack_hartmann"))
    with pytest.raises(ValueError, match=r"must be 'ideal' for IdealSensor; got 'shack_hartmann'"):
        IdealSensor(model.geometry, 0, model.dms[model.config.wfss[0].dm])


def test_loop_state_step_against_numpy(model):
    """forward() = every layer's checked phase() summed per plane, minus B c on the DM discs."""
    atm = model.atmosphere(3, 0.05)
    state = LoopState(model, atm)
    state.reset()
    rng = np.random.default_rng(1)
    command = rng.standard_normal(model.n_modes) * 0.1
    state.apply(command)
    state.evolve_until(0.0123)
    maps = [m.copy() for m in state.forward()]
    for p, plane in enumerate(model.geometry.planes):
        ref = np.zeros((plane.n, plane.n))
        for li in plane.layers:
            ref += atm.layers[li].phase()
        for d in plane.dms:
            dm = model.dms[d]
            ref.ravel()[dm.pixels] -= dm.shapes @ command[model.mode_slices[d]]
        np.testing.assert_allclose(maps[p], ref, rtol=0, atol=1e-12)
    turb = state.turbulence([np.empty_like(m) for m in maps])
    state.reset()
    assert state.t == 0.0 and all(not s.any() for s in state.surfaces)
    state.evolve_until(0.0123)
    for a, b in zip(state.forward(), turb, strict=True):  # flat mirrors: the turbulence
        np.testing.assert_array_equal(a, b)


def test_snapshot_camera_reads_the_loop_maps(model):
    sci = model.science
    dirs = np.array([[0.0, 0.0], [12.5, -7.0]])
    other = sci.looking_at(dirs)
    for v in sci.plane_views():
        v[:] = np.random.default_rng(v.shape[0]).standard_normal(v.shape)
    ref = ScienceCamera(model.geometry, dirs)
    for a, b in zip(ref.plane_views(), sci.plane_views(), strict=True):
        a[:] = b
    np.testing.assert_array_equal(other.forward(), ref.forward())
    np.testing.assert_array_equal(other.residual_phase(1), ref.residual_phase(1))
    sci.reset()
    assert not any(v.any() for v in other.plane_views())


def test_controller_reset_replays():
    """After reset() the same inputs give the same commands as a fresh controller."""
    rng = np.random.default_rng(2)
    inputs = rng.standard_normal((12, 4))
    ctl = Controller(4, gain=0.4, leak=0.01, delay_frames=0.5, integration_frames=1.0)
    first = [ctl.step(m)[0].copy() for m in inputs]
    ctl.reset()
    again = [ctl.step(m)[0].copy() for m in inputs]
    np.testing.assert_array_equal(np.array(first), np.array(again))


def test_a_new_sensor_kind_is_one_class_and_a_registry_entry(model):
    """A kind unknown to the code (an ideal sensor with twice the gain) runs the model.

    Reference: the ideal sensor itself. Its measurements are exactly twice the ideal's
    (a scale by 2 is exact in floating point), and the modal residual it reconstructs is
    the ideal's (the pseudo-inverse halves).
    """
    class Doubled(IdealSensor):
        kind = "doubled"

        def _build(self, cfg) -> None:
            super()._build(cfg)
            self.operators = [2.0 * op for op in self.operators]

    register_sensor_kind(dataclasses.replace(IDEAL, name="doubled", build=Doubled))
    try:
        _check_doubled(model, Doubled)
    finally:
        unregister_sensor_kind("doubled")


def _check_doubled(model, Doubled):
    cfg = model.config
    wfss = tuple(dataclasses.replace(w, kind="doubled" if w.kind == "ideal" else w.kind)
                 for w in cfg.wfss)
    new = LoopModel(cfg.replace(wfss=wfss))
    j = [w.kind for w in cfg.wfss].index("ideal")
    assert type(new.wfss[j]) is Doubled
    maps = [np.random.default_rng(p).standard_normal((pl.n, pl.n))
            for p, pl in enumerate(model.geometry.planes)]
    np.testing.assert_array_equal(new.wfss[j].forward(maps), 2.0 * model.wfss[j].forward(maps))
    sl = model.mode_slices[model.wfss[j].dm.index]
    ideal = model.wfss[j].reconstructor @ model.wfss[j].forward(maps)
    doubled = new.wfss[j].reconstructor @ new.wfss[j].forward(maps)
    np.testing.assert_allclose(doubled, ideal, rtol=1e-9, atol=1e-12 * np.abs(ideal).max())
    assert new.sense(maps, None)[sl].shape == ideal.shape
