"""A new sensor kind and a new mirror kind, written in this file alone, run everywhere.

The kinds below are registered with ``closedloop.kinds`` from this file only (no line of
the package names them): a noiseless ``"perfect_slope"`` Shack-Hartmann with an option
``gain`` (a scale of its slopes) and a ``"noll"`` modal mirror with an option
``first_mode`` (the Noll index of its first mode). Each goes through the config's
rules and its TOML/JSON round trip, the resource estimate, a short closed loop and the
AOT export.

References: the existing kinds they mimic. At ``gain = 1`` and ``first_mode = 2`` they
are the geometric Shack-Hartmann without noise and the Zernike mirror, so every number
of a run (residual variance, logs, measurements), of the estimate and of the export must
be the reference's bit for bit; a non-default option must change the part as its
definition says (slopes scaled exactly by a power of two; the mirror's shapes the Noll
Zernikes of ``modalinfo.bases.zernike_matrix`` from ``first_mode`` on). The registry's
refusals are checked against its documented messages.
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
import pytest

from closedloop import LoopModel, presets, simulate
from closedloop.config import (
    DMConfig,
    FieldConfig,
    SimulationConfig,
    dm_disc_diameter,
    load_config,
    save_config,
)
from closedloop.kinds import (
    MirrorKind,
    SensorKind,
    mirror_kind,
    register_mirror_kind,
    register_sensor_kind,
    sensor_kind,
    unregister_mirror_kind,
    unregister_sensor_kind,
)
from closedloop.optics.dm import ZERNIKE, DeformableMirror
from closedloop.optics.wfs import (
    SHACK_HARTMANN,
    ShackHartmann,
    check_subaperture_sampling,
    slope_count,
    slopes_aot_layout,
    slopes_aot_record,
)
from closedloop.resources import estimate
from modalinfo.bases import noll_to_zernike, zernike_matrix

from .conftest import shrunk

# ---------------------------------------------------------------- a new sensor kind


@dataclass(frozen=True)
class PerfectSlopeOptions:
    """The perfect-slope sensor's own key: ``gain``, a scale of its slopes (> 0)."""

    gain: float = 1.0


class PerfectSlope(ShackHartmann):
    """A Shack-Hartmann without noise whose slopes are scaled by ``options.gain``."""

    kind: ClassVar[str] = "perfect_slope"

    def _build(self, cfg) -> None:
        super()._build(cfg)
        self.noise_rms = 0.0
        if cfg.options.gain != 1.0:
            self.operators = [cfg.options.gain * op for op in self.operators]


def _perfect_slope_rules(w, p: str) -> None:
    if w.noise != 0.0:
        raise ValueError(f"`{p}noise` must be 0 for kind 'perfect_slope'; got {w.noise!r}.")
    if not w.options.gain > 0:
        raise ValueError(f"`{p}gain` must be > 0; got {w.options.gain!r}.")


PERFECT_SLOPE = SensorKind(
    name="perfect_slope", build=PerfectSlope, estimate=SHACK_HARTMANN.estimate,
    aot_record=slopes_aot_record, aot_layout=slopes_aot_layout,
    options=PerfectSlopeOptions, validate=_perfect_slope_rules,
    check=check_subaperture_sampling, measurement_count=slope_count)

# ---------------------------------------------------------------- a new mirror kind


@dataclass(frozen=True)
class NollOptions:
    """The Noll mirror's own key: ``first_mode``, the Noll index of its first mode (>= 2)."""

    first_mode: int = 2


class NollMirror(DeformableMirror):
    """Modal mirror of Noll Zernikes ``first_mode .. first_mode + n_modes - 1``."""

    kind: ClassVar[str] = "noll"

    def _shapes(self, cfg, rho, theta):
        first = cfg.options.first_mode
        modes = list(range(first, first + cfg.n_modes))
        return modes, np.ascontiguousarray(zernike_matrix(modes, rho, theta))


def _noll_rules(d, p: str) -> None:
    first = d.options.first_mode
    if isinstance(first, bool) or not isinstance(first, int) or first < 2:
        raise ValueError(f"`{p}first_mode` must be an int >= 2 (piston is not controlled); "
                         f"got {first!r}.")


def _noll_sampling(cfg: SimulationConfig, i: int) -> None:
    d = cfg.dms[i]
    across = dm_disc_diameter(cfg, i) / (cfg.telescope.diameter / cfg.telescope.n_pixels)
    order = noll_to_zernike(d.options.first_mode + d.n_modes - 1)[0]
    if order > across // 2:
        raise ValueError(f"`dms[{i}].n_modes` must reach a radial order <= {across // 2:g}; "
                         f"got {d.n_modes!r}.")


NOLL = MirrorKind(
    name="noll", build=NollMirror, estimate=ZERNIKE.estimate,
    aot_description=ZERNIKE.aot_description, options=NollOptions, validate=_noll_rules,
    check=_noll_sampling, controlled_modes=lambda cfg, i: cfg.dms[i].n_modes)


@pytest.fixture(scope="module", autouse=True)
def kinds():
    """Register the two kinds for this module's tests, and only for them."""
    register_sensor_kind(PERFECT_SLOPE)
    register_mirror_kind(NOLL)
    yield
    unregister_sensor_kind("perfect_slope")
    unregister_mirror_kind("noll")


# ---------------------------------------------------------------- configurations

DURATION = 5e-3  # 5 frames of 1 ms


def _reference() -> SimulationConfig:
    """table1 made small (two DMs, joint MAP reconstructor), noise-free Shack-Hartmanns."""
    return shrunk(presets.get("table1"), (9, 5), n_subapertures=6, noise=0.0,
                  field=FieldConfig(size=20.0, n_points=3))


def _new_kinds(reference: SimulationConfig, gain: float = 1.0,
               first_mode: int = 2) -> SimulationConfig:
    dms = tuple(dataclasses.replace(d, kind="noll", options=NollOptions(first_mode))
                for d in reference.dms)
    wfss = tuple(dataclasses.replace(w, kind="perfect_slope", options={"gain": gain})
                 for w in reference.wfss)
    return reference.replace(dms=dms, wfss=wfss)


@pytest.fixture(scope="module")
def reference():
    return _reference()


@pytest.fixture(scope="module")
def mimic(reference):
    return _new_kinds(reference)


@pytest.fixture(scope="module")
def runs(reference, mimic):
    return {name: simulate(cfg, DURATION, seed=3, progress=False)
            for name, cfg in (("reference", reference), ("mimic", mimic))}


# ---------------------------------------------------------------- the registry


def test_the_registry_lists_the_new_kinds_and_refuses_clashes():
    import closedloop.config as config_module

    assert "perfect_slope" in config_module.WFS_KINDS and "noll" in config_module.DM_KINDS
    assert sensor_kind("perfect_slope") is PERFECT_SLOPE and mirror_kind("noll") is NOLL
    assert register_sensor_kind(PERFECT_SLOPE) is PERFECT_SLOPE  # the same record again
    with pytest.raises(ValueError, match="^`kind.name` must be a new sensor kind; "
                                         "'perfect_slope' is registered already.$"):
        register_sensor_kind(dataclasses.replace(PERFECT_SLOPE, build=ShackHartmann))
    with pytest.raises(ValueError, match="^`kind.name` must be a new mirror kind; 'zernike'"):
        register_mirror_kind(dataclasses.replace(NOLL, name="zernike"))
    with pytest.raises(ValueError, match=r"^`wfss\[0\].kind` must be one of 'shack_hartmann', "
                                         r"'ideal', 'correlating', 'perfect_slope'; got 'nope'"):
        sensor_kind("nope", "wfss[0].kind")
    with pytest.raises(ValueError, match="^`name` must be a registered mirror kind"):
        unregister_mirror_kind("nope")
    with pytest.raises(TypeError, match="^`kind.build` must be callable"):
        dataclasses.replace(NOLL, build=None)
    with pytest.raises(TypeError, match="^`kind.options` must be a frozen dataclass type"):
        dataclasses.replace(NOLL, options=dict)


def test_the_config_refuses_unknown_kinds_keys_and_bad_options(reference):
    w = reference.wfss[0]
    with pytest.raises(ValueError, match=r"^`wfss\[0\]\.kind` must be one of .*'perfect_slope'; "
                                         r"got 'nope'"):
        reference.replace(wfss=(dataclasses.replace(w, kind="nope"), *reference.wfss[1:]))
    d = reference.to_dict()
    d["wfss"][0].update(kind="perfect_slope", gainz=2.0)
    with pytest.raises(ValueError, match=r"^unknown key `wfss\[0\]\.gainz` in the config"):
        SimulationConfig.from_dict(d)
    d["wfss"][0].pop("gainz")
    d["wfss"][0]["gain"] = -1.0
    with pytest.raises(ValueError, match=r"^`wfss\[0\]\.gain` must be > 0; got -1.0"):
        SimulationConfig.from_dict(d)
    d["wfss"][0].update(kind="shack_hartmann", gain=1.0)  # a key of another kind
    with pytest.raises(ValueError, match=r"^unknown key `wfss\[0\]\.gain` in the config"):
        SimulationConfig.from_dict(d)
    new = _new_kinds(reference)

    def with_dm0(**kw):
        return new.replace(dms=(DMConfig(altitude=0.0, n_modes=9, **kw), new.dms[1]))

    with pytest.raises(TypeError, match=r"^`dms\[0\]\.options` must be None for kind 'zernike' "
                                        r"\(it has no options\); got NollOptions"):
        with_dm0(options=NollOptions())
    with pytest.raises(TypeError, match=r"^`dms\[0\]\.options` must be a NollOptions"):
        with_dm0(kind="noll", options=3)
    with pytest.raises(ValueError, match=r"^`dms\[0\]\.first_mode` must be an int >= 2"):
        with_dm0(kind="noll", options={"first_mode": 1})
    clashing = dataclasses.make_dataclass("Clash", [("n_modes", int, 1)], frozen=True)
    register_mirror_kind(dataclasses.replace(NOLL, name="clash", options=clashing))
    try:
        with pytest.raises(TypeError, match=r"^the options of kind 'clash' must not repeat a "
                                            r"key of `dms\[0\]`; 'n_modes' does"):
            with_dm0(kind="clash")
    finally:
        unregister_mirror_kind("clash")
    with pytest.raises(ValueError, match=r"^`wfss\[1\]\.noise` must be 0 for kind "
                                         r"'perfect_slope'; got 0.01"):
        new.replace(wfss=(new.wfss[0], dataclasses.replace(new.wfss[1], noise=0.01)))


def test_the_kinds_rules_of_the_physics_apply(reference):
    # the joint reconstructor's rule counts the slopes of both WFSs against the two
    # mirrors' modes (controlled_modes of the new kind), whatever their kinds
    slopes = sum(slope_count(reference, j) for j in range(2))
    too_many = _new_kinds(reference).dms[0]
    with pytest.raises(ValueError, match=rf"^`dms\[\*\]\.n_modes` must be <= {slopes} in all"):
        _new_kinds(reference).replace(dms=(dataclasses.replace(too_many, n_modes=slopes),
                                           _new_kinds(reference).dms[1]))


# ---------------------------------------------------------------- the round trips


def test_the_plain_form_holds_the_options_as_keys_and_round_trips(reference, tmp_path):
    cfg = _new_kinds(reference, gain=2.0, first_mode=4)
    plain = cfg.to_dict()
    assert plain["wfss"][0]["gain"] == 2.0 and plain["dms"][1]["first_mode"] == 4
    assert all("options" not in t for t in (*plain["wfss"], *plain["dms"]))
    assert SimulationConfig.from_dict(plain) == cfg
    assert SimulationConfig.from_dict(json.loads(json.dumps(plain))) == cfg
    for suffix in ("toml", "json"):
        assert load_config(save_config(cfg, tmp_path / f"c.{suffix}")) == cfg
    # an option left out takes its default; the built-in kinds' tables have no new key
    del plain["dms"][0]["first_mode"]
    assert SimulationConfig.from_dict(plain).dms[0].options == NollOptions()
    for name in presets.names():  # the presets' files: no new key, the same config back
        preset = presets.get(name)
        plain = preset.to_dict()
        assert all("options" not in t for t in (*plain["wfss"], *plain["dms"])), name
        assert SimulationConfig.from_dict(plain) == preset, name


# ---------------------------------------------------------------- the loop, bit for bit


def test_the_new_kinds_run_the_loop_as_the_kinds_they_mimic(runs):
    ref, new = runs["reference"], runs["mimic"]
    assert ref.residual_variance.shape == (5, 9)
    np.testing.assert_array_equal(new.residual_variance, ref.residual_variance)
    assert sorted(new.logs) == sorted(ref.logs)
    for key in ref.logs:
        np.testing.assert_array_equal(new.logs[key].coeffs, ref.logs[key].coeffs)
    for a, b in zip(new.measurements, ref.measurements, strict=True):
        np.testing.assert_array_equal(a, b)


def test_the_options_reach_the_built_parts(reference):
    base = LoopModel(reference)
    model = LoopModel(_new_kinds(reference, gain=2.0, first_mode=4))
    assert [type(d) for d in model.dms] == [NollMirror] * 2
    assert [type(w) for w in model.wfss] == [PerfectSlope] * 2
    maps = [np.random.default_rng(p).standard_normal((pl.n, pl.n))
            for p, pl in enumerate(base.geometry.planes)]
    for w, ref in zip(model.wfss, base.wfss, strict=True):  # a scale by 2 is exact
        np.testing.assert_array_equal(w.forward(maps), 2.0 * ref.forward(maps))
    for d, ref in zip(model.dms, base.dms, strict=True):
        assert d.modes == list(range(4, 4 + ref.n_modes))
        assert d.labels[0] == "Z4"
        coords = base.geometry.plane_coords(d.plane)
        yy, xx = np.meshgrid(coords, coords, indexing="ij")
        rho = (np.hypot(xx, yy) / (d.diameter / 2.0)).ravel()[d.pixels]
        theta = np.arctan2(yy, xx).ravel()[d.pixels]
        np.testing.assert_allclose(d.shapes, zernike_matrix(d.modes, rho, theta),
                                   rtol=0, atol=1e-12)


def test_the_resource_estimate_is_the_mimicked_kinds(reference, mimic):
    for kwargs in ({}, {"oracle": True, "budget": True}):
        a, b = estimate(mimic, 0.5, **kwargs), estimate(reference, 0.5, **kwargs)
        assert (a.parts, a.drivers, a.peak_bytes, a.seconds_per_frame, a.n_frames) == (
            b.parts, b.drivers, b.peak_bytes, b.seconds_per_frame, b.n_frames)
    assert a.drivers["dm_shapes"].endswith("].n_modes")  # the new kind's own key


def test_the_aot_export_writes_the_new_kinds_as_the_mimicked_ones(runs, tmp_path):
    aotpy = pytest.importorskip("aotpy")
    from closedloop.aot import export_aot

    systems = {}
    for name, run in runs.items():
        path = export_aot(run, tmp_path / f"{name}.fits")
        systems[name] = aotpy.AOSystem.read_from_file(path)
    ref, new = systems["reference"], systems["mimic"]
    for a, b in zip(new.wavefront_sensors, ref.wavefront_sensors, strict=True):
        assert type(a) is type(b) is aotpy.ShackHartmann
        assert a.n_valid_subapertures == b.n_valid_subapertures
        np.testing.assert_array_equal(np.asarray(a.measurements.data),
                                      np.asarray(b.measurements.data))
        np.testing.assert_array_equal(np.asarray(a.subaperture_mask.data),
                                      np.asarray(b.subaperture_mask.data))
    for a, b in zip(new.wavefront_correctors, ref.wavefront_correctors, strict=True):
        assert a.n_valid_actuators == b.n_valid_actuators
    for a, b in zip(sorted(new.loops, key=lambda lp: lp.uid),
                    sorted(ref.loops, key=lambda lp: lp.uid), strict=True):
        assert a.uid == b.uid
        for field in ("modal_coefficients", "measurements_to_modes", "commands"):
            x, y = getattr(a, field), getattr(b, field)
            assert (x is None) == (y is None)
            if x is not None:
                np.testing.assert_array_equal(np.asarray(x.data), np.asarray(y.data))
