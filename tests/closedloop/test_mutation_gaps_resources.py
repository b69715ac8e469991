"""closedloop.resources: each part of the estimate, the peak, the time, the refusals.

Gaps found by mutation testing (docs/MUTATION.md, "kinds.py, resources.py, predictors.py,
training.py"). No model is built; every test only estimates. References, from outside
the module's code:

- the Gram phase of the streamed budget against the ``nbytes`` of the arrays
  :class:`closedloop.budget.IdealSensing` allocates at once (``_gram``: the ``M x M``
  Gram matrix, the two index arrays of its strict upper triangle, ``np.triu_indices``,
  and one block of :data:`~closedloop.resources.GRAM_ROWS` rows of ``G``), allocated
  here with numpy at the shapes it uses;
- the byte counts the module docstring names, written out here from the shapes: a layer
  screen ``G**2`` float64 with ``G`` from :func:`closedloop.optics.atmosphere.screen_size`
  (another module), twice with the oracle; plane maps 3 (oracle: 5) float64 per plane
  pixel; the pupil's 5 ``N x N`` float64 grids; the reconstructor's 6 dense float64
  ``measurements x modes`` matrices; the logs' ``frames x (3 M + directions +
  measurements)`` float64, twice; each WFS's build at 16 bytes per sparse entry of its
  kind's :class:`~closedloop.kinds.SensorCost`; the peak ``baseline + max(set-up,
  run)`` with the phases of the docstring. The kinds' costs (``closedloop.kinds``
  records, defined in the optics modules) are the inputs;
- the time per frame against the CPU per frame measured on the presets it was fitted to
  (benchmarks/RESULTS.md, "Cost models against measured, round 11": table1 1.22 ms,
  kaos 0.34 ms, ``est_mcao_variant(16)`` 7.8 ms; within 1.5x); the SVD's time against
  the measurement its constant quotes (4.7 s for a 2,900 x 1,583 pseudo-inverse);
- the project's rule for refusals: one line naming the key, the estimate and the limit.
"""

from __future__ import annotations

import dataclasses
import math
import re
from types import SimpleNamespace

import numpy as np
import pytest

from closedloop import presets
from closedloop import resources as res
from closedloop.config import SimulationConfig
from closedloop.kinds import SensorCost, mirror_kind, sensor_kind
from closedloop.optics.atmosphere import screen_size
from closedloop.optics.geometry import n_field_samples, plane_layout
from modalinfo.common.sizes import format_size

from .conftest import small, with_values


# ---------------------------------------------------------------- the streamed Gram phase
def _ideal_cost(config, n_modes, entries=0.0, n_meas=1.0, wfs_build=0.0):
    """A hand-made ideal model's cost: ``n_modes`` modes, tiny sensors."""
    costs = [SensorCost(n_measurements=n_meas, build_entries=entries) for _ in config.wfss]
    return res._ModelCost(pupil=0.0, dm_bytes=0.0, dm_key="", n_modes=n_modes,
                        setup_seconds=0.0, dm_build=0.0, dm_build_key="", costs=costs,
                        wfs_build=wfs_build, build_key="", n_meas=n_meas * len(costs),
                        kept_operators=0.0)


@pytest.mark.parametrize("m", [624, 1500])
def test_the_gram_phase_is_the_arrays_ideal_sensing_allocates(m):
    """The planted bug that halved it escaped every test before this one."""
    config = presets.est_mcao_variant(16)
    # IdealSensing._gram holds at once: the Gram matrix, the strict upper triangle's
    # two index arrays, one block of GRAM_ROWS rows of G (all modes)
    gram = np.zeros((m, m), order="F")
    upper = np.triu_indices(m, 1)
    block = np.empty((res.GRAM_ROWS, m))
    held = gram.nbytes + upper[0].nbytes + upper[1].nbytes + block.nbytes
    kept, transient = res._streamed_budget(_ideal_cost(config, m))
    # the estimate rounds the triangle up to M x M (8 M bytes more)
    assert transient == pytest.approx(held, rel=1e-3)
    assert transient >= held
    assert kept == pytest.approx(gram.nbytes, rel=1e-12)  # the M x M reconstruction


def test_the_gram_phase_reaches_the_estimate_of_a_streamed_budget(monkeypatch):
    config = presets.est_mcao_variant(16)
    assert res.budget_streams(config)
    base = res.estimate(config, 0.01, budget=True)
    # a larger GRAM_ROWS, the block of G formed at once, must raise the peak by its bytes
    # when the Gram phase is what peaks (M = 624 modes)
    m = sum(d.n_modes for d in config.dms)
    monkeypatch.setattr(res, "GRAM_ROWS", 100 * res.GRAM_ROWS)
    wide = res.estimate(config, 0.01, budget=True)
    assert wide.peak_bytes - base.peak_bytes == pytest.approx(
        8.0 * 99 * 4096 * m - _build_excess(config), rel=1e-6, abs=1.0)


def _build_excess(config) -> float:
    """Bytes by which the largest ideal sensor's build exceeded the Gram phase."""
    dx = config.telescope.diameter / config.telescope.n_pixels
    ideal = res._model(res.ideal_sensor_config(config), plane_layout(config), dx)
    m = ideal.n_modes
    return max(0.0, ideal.wfs_build - 8.0 * (2 * m * m + 4096 * m))


@pytest.mark.parametrize("n_meas", [1.0, 1e6])
def test_no_dense_own_block_only_the_largest_build_or_the_gram_phase(n_meas):
    # IdealSensing never forms a sensor's dense interaction with its own mirror
    # (WavefrontSensor.interaction is built on first use; tests/closedloop/
    # test_budget_streamed.py checks it is never formed): sensors of 1e6 measurements
    # cost no 1e6 x modes block. While built: the largest sensor's build (wfs_build),
    # then the Gram phase, the larger of the two
    config = presets.est_mcao_variant(16)
    m = sum(d.n_modes for d in config.dms)
    gram = np.zeros((m, m), order="F")
    upper = np.triu_indices(m, 1)
    block = np.empty((res.GRAM_ROWS, m))
    held = gram.nbytes + upper[0].nbytes + upper[1].nbytes + block.nbytes
    small_build = _ideal_cost(config, m, entries=1e5, n_meas=n_meas, wfs_build=3e5)
    kept, transient = res._streamed_budget(small_build)
    # the Gram phase, whatever the measurement count (a dense own block would be
    # 8 B x 1e6 x a mirror's modes, 1.6 GB and more)
    assert transient == pytest.approx(held, rel=1e-3)
    big_build = _ideal_cost(config, m, entries=1e5, n_meas=n_meas, wfs_build=3e10)
    assert res._streamed_budget(big_build)[1] == 3e10            # the build, alone
    # kept: the ideal operators at 16 B per kept entry (their share of the built) and
    # the M x M reconstruction
    entries = 1e5 * len(config.wfss)
    assert kept == pytest.approx(res._IDEAL_KEPT_SHARE * 16.0 * entries + gram.nbytes,
                                 rel=1e-12)


# ---------------------------------------------------------------- every part by hand
def _by_hand(config: SimulationConfig, duration: float, oracle: bool = False,
             budget: bool = False) -> dict:
    """The parts and phases of the module docstring, from the shapes and kinds' costs."""
    tel = config.telescope
    dx = tel.diameter / tel.n_pixels
    frames = max(1, round(duration / config.loop.time_step))
    total = (frames + config.loop.delay_frames + 1) * config.loop.time_step
    layout = plane_layout(config)
    side = {p: n for p, (_, n, _, _) in enumerate(layout)}

    def plane_of(index, slot):
        return next(p for p, entry in enumerate(layout) if index in entry[slot])

    gs = []
    for i, layer in enumerate(config.layers):
        n = side[plane_of(i, 2)]
        a = math.radians(layer.wind_direction)
        v = (layer.wind_speed * math.cos(a), layer.wind_speed * math.sin(a))
        gs.append(screen_size(n, dx, v, total, max(4096, 4 * n)))
    screens = sum(8.0 * g * g for g in gs) * (2 if oracle else 1)
    transient = 40.0 * max(gs) ** 2

    def model(cfg):
        mirrors = [mirror_kind(d.kind).estimate(cfg, i, dx) for i, d in enumerate(cfg.dms)]
        sensors = [sensor_kind(w.kind).estimate(cfg, j, len(layout), dx)
                   for j, w in enumerate(cfg.wfss)]
        held = [16.0 * (c.build_entries if c.held_entries is None else c.held_entries)
                for c in sensors]
        return {"pupil": 5 * 8.0 * tel.n_pixels ** 2,
                "dm": sum(c.shape_bytes + 5 * 8.0 * side[plane_of(i, 3)] ** 2
                          for i, c in enumerate(mirrors)),
                "dm_build": max([0.0] + [c.build_bytes for c in mirrors]),
                "modes": sum(c.n_modes for c in mirrors),
                "meas": sum(c.n_measurements for c in sensors),
                "build": max(held),
                "ops": 0.1 * 16.0 * sum(c.build_entries for c in sensors),
                "entries": sum(c.build_entries for c in sensors), "sensors": sensors}

    run_model = model(config)
    dirs = config.field.n_points ** 2
    parts = {"baseline": 350e6, "pupil": run_model["pupil"], "screens": screens,
             "planes": (5 if oracle else 3) * 8.0 * sum(n * n for n in side.values()),
             "dm_shapes": run_model["dm"],
             "wfs_build": run_model["build"] + run_model["ops"],
             "reconstructor": 6 * 8.0 * run_model["meas"] * run_model["modes"],
             "logs": 2 * 8.0 * frames * (3 * run_model["modes"] + dirs + run_model["meas"])}
    if run_model["dm_build"] > 0:
        parts["dm_build"] = run_model["dm_build"]
    kept = parts["pupil"] + parts["dm_shapes"] + parts["reconstructor"] + run_model["ops"]
    setup = (parts["pupil"] + parts["dm_shapes"]
             + max(parts["wfs_build"], run_model["dm_build"]))
    run = kept + screens + parts["planes"] + parts["logs"]
    if budget:
        ideal = model(res.ideal_sensor_config(config))
        if res.budget_streams(config):
            m = ideal["modes"]
            ideal_kept = 0.35 * 16.0 * ideal["entries"] + 8.0 * m * m
            # the largest sensor's build, then the Gram phase (no dense own block)
            ideal_setup = ideal_kept + max(ideal["build"], 8.0 * (2 * m * m + 4096 * m))
        else:
            ideal_kept = (ideal["pupil"] + ideal["dm"] + 48.0 * ideal["meas"] * ideal["modes"]
                          + ideal["ops"])
            ideal_setup = (ideal["pupil"] + ideal["dm"]
                           + max(ideal["build"] + ideal["ops"], ideal["dm_build"]))
        parts["budget"] = ideal_kept
        run = max(run + ideal_kept, kept + screens + ideal_setup)
    peak = 350e6 + max(setup, kept + screens + transient, run)
    return {"parts": parts, "setup": setup, "run": run, "peak": peak, "frames": frames}


CASES = {
    "small table1": lambda: (small(), 0.05, False, False),
    "small table1, oracle and budget": lambda: (small(), 0.2, True, True),
    "small mcao3, budget": lambda: (small("mcao3"), 0.013, False, True),
    # ideal sensors of 91 field samples: their build outweighs the kept budget model
    "small table1, budget of wide ideal sensors": lambda: (SimulationConfig.from_dict({
        **small().to_dict(), "wfss": [{**w, "field_samples": 6}
                                       for w in small().to_dict()["wfss"]]}),
        0.002, False, True),
    "kaos, oracle": lambda: (presets.get("kaos"), 0.3, True, False),
    "dkist-scao, budget (dense)": lambda: (presets.get("dkist-scao"), 0.05, False, True),
    "est-mcao@16, budget (streamed)": lambda: (presets.est_mcao_variant(16), 0.01, True, True),
    "est-mcao, budget (streamed)": lambda: (presets.get("est-mcao"), 0.05, False, True),
    "est-mcao-solar": lambda: (presets.get("est-mcao-solar"), 0.02, False, False),
    # a 20-s run: the wind's travel asks more than the 4096-pixel cap
    "small table1, capped screens": lambda: (small(), 20.0, False, False),
    # a layer 1000 km up: its plane (3,318 px) caps its screen at 4 n, above 4096
    "small table1, a layer at 1000 km": lambda: (
        with_values(small(), "layers", 1, altitude=1e6), 0.01, False, False),
}


@pytest.mark.parametrize("case", list(CASES))
def test_every_part_and_phase_is_the_arrays_the_docstring_names(case):
    config, duration, oracle, budget = CASES[case]()
    want = _by_hand(config, duration, oracle, budget)
    est = res.estimate(config, duration, oracle=oracle, budget=budget)
    assert set(est.parts) == set(want["parts"])
    for name, value in want["parts"].items():
        assert est.parts[name] == pytest.approx(value, rel=1e-9), name
    assert est.setup_bytes == pytest.approx(want["setup"], rel=1e-9)
    assert est.run_bytes == pytest.approx(want["run"], rel=1e-9)
    assert est.peak_bytes == pytest.approx(want["peak"], rel=1e-9)
    assert est.n_frames == want["frames"] and isinstance(est.n_frames, int)
    assert est.seconds == pytest.approx(est.n_frames * est.seconds_per_frame, rel=1e-12)


def test_the_screens_cover_the_run_the_delay_and_one_frame():
    # screen_size's duration: (frames + delay_frames + 1) x time_step (the command's
    # hold past the last frame). A run length where one frame more or less, or the delay
    # counted the other way, changes the fastest screen's size (found by search here)
    cfg = small()
    loop = cfg.loop
    assert loop.delay_frames > 0
    dx = cfg.telescope.diameter / cfg.telescope.n_pixels
    layout = plane_layout(cfg)
    top = len(cfg.layers) - 1
    n = next(n for _, n, layers, _ in layout if top in layers)
    layer = cfg.layers[top]
    a = math.radians(layer.wind_direction)
    v = (layer.wind_speed * math.cos(a), layer.wind_speed * math.sin(a))

    def side(extra_frames):
        return screen_size(n, dx, v, extra_frames * loop.time_step, max(4096, 4 * n))

    frames = next(f for f in range(300, 3000)
                  if len({side(f + loop.delay_frames + 1), side(f + loop.delay_frames - 1),
                          side(f - loop.delay_frames + 1)}) == 3)
    duration = frames * loop.time_step
    est = res.estimate(cfg, duration)
    assert est.n_frames == frames
    assert est.parts["screens"] == pytest.approx(
        _by_hand(cfg, duration)["parts"]["screens"], rel=1e-12)


def test_the_frame_count_rounds_and_counts_at_least_one():
    cfg = small()
    dt = cfg.loop.time_step
    assert res.estimate(cfg, 10.4 * dt).n_frames == 10
    assert res.estimate(cfg, 10.6 * dt).n_frames == 11
    assert res.estimate(cfg, 0.3 * dt).n_frames == 1


@pytest.mark.parametrize("duration", [0.0, -1.0, math.nan, math.inf])
def test_a_duration_outside_the_frame_range_is_refused_whole(duration):
    cfg = small()
    dt = cfg.loop.time_step
    msg = (f"`duration` must be a finite number of seconds > 0 and at most 1e+15 frames of "
           f"loop.time_step = {dt:g} s; got {duration:g} s.")
    with pytest.raises(res.ResourceError, match="^" + re.escape(msg) + "$"):
        res.estimate(cfg, duration)


def test_the_frame_limit_is_exclusive():
    cfg = small()
    dt = cfg.loop.time_step
    with pytest.raises(res.ResourceError):
        res.estimate(cfg, res.MAX_FRAMES * dt)
    assert res.estimate(cfg, 1e14 * dt).n_frames == 10 ** 14


def test_a_config_of_another_type_is_refused():
    with pytest.raises(TypeError, match=r"^`config` must be a SimulationConfig; got dict\.$"):
        res.estimate(small().to_dict(), 0.1)


# ---------------------------------------------------------------- drivers
def test_the_drivers_name_the_keys_that_set_each_part():
    cfg = small()
    est = res.estimate(cfg, 0.05, budget=True)
    assert est.drivers["baseline"] == "-" and est.drivers["pupil"] == "telescope.n_pixels"
    assert est.drivers["reconstructor"] == "dms[*].n_modes` x `wfss[*].n_subapertures"
    assert est.drivers["budget"] == "budget_every"
    assert est.drivers["logs"] == "duration"
    # the mirror whose shapes and plane grids (5 float64 maps) weigh most
    dx = cfg.telescope.diameter / cfg.telescope.n_pixels
    layout = plane_layout(cfg)
    costs = [mirror_kind(d.kind).estimate(cfg, i, dx) for i, d in enumerate(cfg.dms)]
    sizes = [c.shape_bytes + 40.0 * next(n for _, n, _, dms in layout if i in dms) ** 2
             for i, c in enumerate(costs)]
    assert est.drivers["dm_shapes"] == costs[int(np.argmax(sizes))].driver
    assert est.parts["dm_shapes"] == pytest.approx(sum(sizes), rel=1e-12)
    # a 31 x 31 field grid: a log row holds more directions (961) than 3 M + measurements
    wide = with_values(cfg, "field", None, n_points=31)
    assert res.estimate(wide, 0.05).drivers["logs"] == "field.n_points"
    # the plane maps' size is the largest plane's: the highest layer's
    assert est.drivers["planes"] == f"layers[{len(cfg.layers) - 1}].altitude"
    # the logs' key: the field grid once its directions outnumber the rest of a row
    # (28 modes on the ground DM: 19^2 = 361 directions, just above 3 M + 201 = 345)
    for base in (cfg, with_values(cfg, "dms", 0, n_modes=28)):
        dx = base.telescope.diameter / base.telescope.n_pixels
        rest = 3 * sum(d.n_modes for d in base.dms) + sum(
            sensor_kind(w.kind).estimate(base, j, len(plane_layout(base)), dx).n_measurements
            for j, w in enumerate(base.wfss))
        keys = {}
        for n in range(3, 40, 2):
            grid = with_values(base, "field", None, n_points=n)
            keys[n] = res.estimate(grid, 0.05).drivers["logs"]
            assert keys[n] == ("field.n_points" if n * n > rest else "duration"), n
        assert set(keys.values()) == {"field.n_points", "duration"}


def test_the_wfs_build_is_blamed_on_field_samples_or_on_the_largest_plane():
    cfg = small()
    samples = n_field_samples(cfg.wfss[0].field_of_view, cfg.wfss[0].field_samples)
    key = res.estimate(cfg, 0.05).drivers["wfs_build"]
    if samples > 1:
        assert key.startswith("wfss[") and f"({samples} directions) x `telescope.n_pixels" \
            in key
    # one sample per WFS: the largest plane's key; with equal builds the last WFS's
    one = SimulationConfig.from_dict({**cfg.to_dict(), "wfss": [
        {**w, "field_samples": 1} for w in cfg.to_dict()["wfss"]]})
    assert res.estimate(one, 0.05).drivers["wfs_build"] == res._plane_driver(
        one, plane_layout(one), res._biggest_plane(plane_layout(one)))
    three = SimulationConfig.from_dict({**cfg.to_dict(), "wfss": [
        {**w, "field_samples": 3} for w in cfg.to_dict()["wfss"]]})
    n3 = n_field_samples(three.wfss[0].field_of_view, 3)
    assert n3 == 19
    builds = [16.0 * (c.build_entries if c.held_entries is None else c.held_entries)
              for c in res._sensor_costs(three, len(plane_layout(three)), 0.125)]
    j = max(j for j, b in enumerate(builds) if b == max(builds))
    assert res.estimate(three, 0.05).drivers["wfs_build"] == (
        f"wfss[{j}].field_samples` (19 directions) x `telescope.n_pixels")


def test_the_screen_is_blamed_on_the_duration_exactly_where_the_travel_sets_its_size():
    # screen_size's law: G = next_fast_len(max(4 n, n + 3 + travel)), travel the wind's
    # pixels over the run; the wind's travel sets G (the key is `duration`) from
    # n + 3 + travel > 4 n on. The highest layer blows along x (then along y).
    cfg = small()
    top = len(cfg.layers) - 1
    dx = cfg.telescope.diameter / cfg.telescope.n_pixels
    for direction in (0.0, 90.0):
        windy = with_values(cfg, "layers", top, wind_speed=20.0, wind_direction=direction)
        layout = plane_layout(windy)
        p = next(k for k, entry in enumerate(layout) if top in entry[2])
        n = layout[p][1]
        assert res._biggest_plane(layout) == p
        for excess, key in ((0.5, "duration"), (-0.5, f"layers[{top}].altitude")):
            total = (3 * n - 3 + excess) * dx / 20.0
            assert res._screens(windy, layout, dx, total)[2] == key, (direction, excess)


def test_a_wfs_without_a_field_has_one_direction_whatever_its_rings():
    cfg = small()
    d = cfg.to_dict()
    for w in d["wfss"]:
        w.update(field_of_view=0.0, field_samples=3)
    on_axis = SimulationConfig.from_dict(d)
    assert n_field_samples(0.0, 3) == 1
    layout = plane_layout(on_axis)
    assert res.estimate(on_axis, 0.05).drivers["wfs_build"] == res._plane_driver(
        on_axis, layout, res._biggest_plane(layout))


def test_the_plane_driver_is_the_pupil_a_layer_or_a_mirror():
    cfg = small()
    layout = plane_layout(cfg)
    n_pix = cfg.telescope.n_pixels
    # a plane no wider than the pupil and its margins (N + 2 x 3 + 1) is the pupil's
    fake = [(0.0, n_pix + 7, (0,), (0,)), (5e3, n_pix + 8, (1,), (1,)),
            (9e3, n_pix + 8, (), (2,))]
    assert res._plane_driver(cfg, fake, 0) == "telescope.n_pixels"
    assert res._plane_driver(cfg, fake, 1) == "layers[1].altitude"
    assert res._plane_driver(cfg, fake, 2) == "dms[2].altitude"
    assert res._biggest_plane(fake) == 1  # the first of a tie
    assert res._biggest_plane(layout) == max(range(len(layout)), key=lambda p: layout[p][1])


def test_the_screens_are_blamed_on_the_duration_when_the_wind_travel_sets_them():
    cfg = small()
    # a 1 h run: the screen is the wind's travel, not the plane
    est = res.estimate(cfg, 20.0)
    assert est.drivers["screens"] == "duration"
    # a short run: the largest screen is the widest plane's, the highest layer's
    short = res.estimate(cfg, 0.01)
    assert short.drivers["screens"] == f"layers[{len(cfg.layers) - 1}].altitude"


def test_the_largest_part_and_its_driver_leave_the_baseline_out():
    est = res.ResourceEstimate(parts={"baseline": 9.0, "pupil": 1.0, "logs": 3.0},
                             drivers={"baseline": "-", "pupil": "p", "logs": "duration"})
    assert est.largest == "logs" and est.driver == "duration"
    empty = res.ResourceEstimate()
    assert (empty.peak_bytes, empty.n_frames, empty.seconds_per_frame, empty.setup_bytes,
            empty.run_bytes, empty.setup_seconds, empty.parts) == (0.0, 0, 0.0, 0.0, 0.0,
                                                                    0.0, {})


def test_describe_writes_the_peak_each_part_largest_first_and_the_time():
    est = res.ResourceEstimate(parts={"baseline": 2e8, "pupil": 3e9, "logs": 5e5},
                             drivers={"baseline": "-", "pupil": "telescope.n_pixels"},
                             peak_bytes=4e9, n_frames=100, seconds_per_frame=9.99e-3,
                             setup_seconds=0.0)
    text = est.describe().split("\n")
    assert text[0] == (f"estimated peak memory {format_size(4e9)} (100 frames, about "
                       "0.999 s of loop at 9.99 ms/frame)")
    assert text[1] == f"  {'pupil':<14}{format_size(3e9):>10}   driven by `telescope.n_pixels`"
    assert text[2] == f"  {'baseline':<14}{format_size(2e8):>10}   driven by -"
    assert text[3] == f"  {'logs':<14}{format_size(5e5):>10}   driven by -"
    assert len(text) == 4
    costly = res.ResourceEstimate(parts={"baseline": 1.0}, drivers={}, n_frames=1,
                                seconds_per_frame=1.0, setup_seconds=12.34)
    assert costly.describe().split("\n")[1] == "  set-up builds about 12.3 s of CPU"
    brief = res.ResourceEstimate(parts={"baseline": 1.0}, drivers={}, setup_seconds=0.5)
    assert brief.describe().split("\n")[1] == "  set-up builds about 0.5 s of CPU"


# ---------------------------------------------------------------- time
@pytest.mark.parametrize(("name", "measured"), [("table1", 1.22e-3), ("kaos", 0.34e-3),
                                              ("est16", 7.8e-3)])
def test_the_time_per_frame_is_within_1_5x_of_the_cpu_measured(name, measured):
    config = presets.est_mcao_variant(16) if name == "est16" else presets.get(name)
    est = res.estimate(config, 0.1)
    assert 1 / 1.5 < est.seconds_per_frame / measured < 1.5


def test_the_time_per_frame_grows_with_each_part_of_the_frame_work():
    cfg = small()
    base = res.estimate(cfg, 0.05).seconds_per_frame
    # each of these adds work per frame: more science directions, more modes, more pixels
    for changed in (with_values(cfg, "field", None, n_points=9),
                    with_values(cfg, "dms", 0, n_modes=54),
                    with_values(cfg, "telescope", None, n_pixels=40)):
        assert res.estimate(changed, 0.05).seconds_per_frame > base


def test_a_sensor_s_frame_time_is_added_and_the_largest_named():
    costs = [SensorCost(1.0, 1.0), SensorCost(1.0, 1.0, 0.5, "wfss[1].image_formation"),
             SensorCost(1.0, 1.0, 2.0, "wfss[2].image_formation"),
             SensorCost(1.0, 1.0, 1.0, "wfss[3].image_formation"),
             SensorCost(1.0, 1.0, 7.0, "")]  # no key: not an imaging sensor
    assert res._frame_seconds(costs) == (3.5, "wfss[2].image_formation")
    assert res._frame_seconds([SensorCost(1.0, 1.0)]) == (0.0, "")
    # one imaging sensor under a second a frame is still named
    assert res._frame_seconds([SensorCost(1.0, 1.0, 0.5, "wfss[0].image_formation")]) == (
        0.5, "wfss[0].image_formation")


def test_the_sensors_frame_time_adds_to_the_time_per_frame(monkeypatch):
    cfg = small()
    real = res._sensor_costs
    base = res.estimate(cfg, 0.05).seconds_per_frame

    def imaging(config, n_planes, dx):
        costs = real(config, n_planes, dx)
        return [SensorCost(c.n_measurements, c.build_entries, 0.25 * (j + 1),
                           f"wfss[{j}].image_formation", c.held_entries)
                for j, c in enumerate(costs)]

    monkeypatch.setattr(res, "_sensor_costs", imaging)
    added = sum(0.25 * (j + 1) for j in range(len(cfg.wfss)))
    assert res.estimate(cfg, 0.05).seconds_per_frame == pytest.approx(base + added,
                                                                      rel=1e-12)


def test_the_svd_time_is_its_measurement_and_small_ones_are_not_reported(monkeypatch):
    # 4.7 s measured for the 2,900 x 1,583 pseudo-inverse of a DKIST-like 43 x 43 SH
    assert 6.5e-10 * 2900 * 1583 ** 2 == pytest.approx(4.7, rel=0.03)
    config = presets.get("dkist-scao")
    dx = config.telescope.diameter / config.telescope.n_pixels
    costs = res._sensor_costs(config, len(plane_layout(config)), dx)
    rows = sum(c.n_measurements for c in costs)
    cols = mirror_kind(config.dms[0].kind).estimate(config, 0, dx).n_modes
    # through the Gram matrix (the actuator DM's large products): 0.7 s, not reported
    assert 8.0 * rows * cols >= res.GRAM_MIN_BYTES
    assert 1.7e-10 * rows * cols * min(rows, cols) < 1.0
    assert res._svd_seconds(config, costs) == 0.0
    # gesdd's rate where the Gram path is off: 2.7 s
    monkeypatch.setattr(res, "GRAM_MIN_BYTES", math.inf)
    want = 6.5e-10 * rows * cols * min(rows, cols)
    assert want > 1.0
    assert res._svd_seconds(config, costs) == pytest.approx(want, rel=1e-9)
    # and the Gram rate where it is on, from 1 s
    monkeypatch.setattr(res, "GRAM_MIN_BYTES", 8.0)
    monkeypatch.setattr(res, "_COSTLY_SECONDS", 0.5)
    assert res._svd_seconds(config, costs) == pytest.approx(
        1.7e-10 * rows * cols * min(rows, cols), rel=1e-9)
    # table1's are milliseconds: 0; a zonal mirror has none
    cfg = small()
    assert res._svd_seconds(cfg, res._sensor_costs(cfg, 3, 0.125)) == 0.0
    lag = with_values(cfg, "dms", 0, kind="ideal")
    assert res._svd_seconds(lag, res._sensor_costs(lag, 3, 0.125)) == 0.0


def test_the_joint_svd_and_map_times_follow_their_flop_counts():
    config = presets.est_mcao_variant(32)
    dx = config.telescope.diameter / config.telescope.n_pixels
    costs = res._sensor_costs(config, len(plane_layout(config)), dx)
    m = sum(c.n_measurements for c in costs)
    n = sum(mirror_kind(d.kind).estimate(config, i, dx).n_modes
            for i, d in enumerate(config.dms))
    assert config.loop.reconstructor == "map"
    # the MAP's Cholesky: 2 m n^2 + 4/3 n^3 flops at 2e-11 s (1.78 s measured here)
    got = res._svd_seconds(config, costs)
    assert got == pytest.approx(2e-11 * (2 * m * n * n + 4 / 3 * n ** 3), rel=1e-9)
    assert got == pytest.approx(1.78, rel=0.15)
    svd = config.replace(loop=config.loop.__class__(**{**vars(config.loop),
                                                       "reconstructor": "truncated"}))
    gram = 8.0 * m * n >= res.GRAM_MIN_BYTES
    per = 1.7e-10 if gram else 6.5e-10
    assert res._svd_seconds(svd, costs) == pytest.approx(per * m * n * min(m, n), rel=1e-9)


def test_the_mirrors_build_is_blamed_on_the_largest_build_s_key():
    config = presets.get("est-mcao")
    dx = config.telescope.diameter / config.telescope.n_pixels
    costs = [mirror_kind(d.kind).estimate(config, i, dx) for i, d in enumerate(config.dms)]
    largest = max(costs, key=lambda c: c.build_bytes)
    est = res.estimate(config, 0.01)
    assert est.parts["dm_build"] == largest.build_bytes > 0
    assert est.drivers["dm_build"] == largest.driver and largest.driver.startswith("dms[")


def test_the_reconstructor_s_time_by_its_form_and_the_mirrors_kinds(monkeypatch):
    """The docstring's rules on a config stand-in: a plain kind (no `large_products`)."""
    from closedloop import kinds
    from closedloop.kinds import MirrorCost

    def plain_build(geometry, index):
        raise AssertionError("not built")

    def plain_estimate(config, i, dx):  # modes per pupil pixel: 300 (+100) at D / N
        return MirrorCost(n_modes=(300.0 + 100 * i) * 0.125 / dx, shape_bytes=0.0,
                          ops_per_pixel=1.0, driver=f"dms[{i}].n_modes")

    class LargeBuild:  # a kind whose mirrors take the 4-m loops' algebra
        large_products = True

    kinds.register_mirror_kind(dataclasses.replace(
        mirror_kind("zernike"), name="probe_plain", build=plain_build, estimate=plain_estimate))
    kinds.register_mirror_kind(dataclasses.replace(
        mirror_kind("zernike"), name="probe_large", build=LargeBuild, estimate=plain_estimate))
    monkeypatch.setattr(res, "_COSTLY_SECONDS", 0.0)  # every time reported
    try:
        def cfg(kinds_, form="truncated"):
            return SimpleNamespace(
                dms=tuple(SimpleNamespace(kind=k) for k in kinds_),
                wfss=tuple(SimpleNamespace(dm=i) for i in range(len(kinds_))),
                telescope=SimpleNamespace(diameter=4.0, n_pixels=32),
                loop=SimpleNamespace(reconstructor=form))

        costs = [SensorCost(1000.0, 0.0), SensorCost(800.0, 0.0)]
        monkeypatch.setattr(res, "GRAM_MIN_BYTES", 8.0)
        # one mirror: each WFS's pseudo-inverse with it, gesdd's rate without large products
        one = res._svd_seconds(cfg(["probe_plain"]), costs[:1])
        assert one == pytest.approx(6.5e-10 * 1000 * 300 * 300, rel=1e-12)
        # one mirror asks no MAP (a joint reconstructor needs several)
        assert res._svd_seconds(cfg(["probe_plain"], "map"), costs[:1]) == one
        # one mirror seen by two WFSs of fewer measurements than its modes: one
        # pseudo-inverse per WFS (rows x cols x rows each), not a joint one
        two_wfs = cfg(["probe_plain"])
        two_wfs.wfss = (SimpleNamespace(dm=0), SimpleNamespace(dm=0))
        few = [SensorCost(200.0, 0.0), SensorCost(250.0, 0.0)]
        assert res._svd_seconds(two_wfs, few) == pytest.approx(
            6.5e-10 * 200 * 300 * 200 + 6.5e-10 * 250 * 300 * 250, rel=1e-12)
        # reported from _COSTLY_SECONDS on, inclusive (the same product, the same bits)
        monkeypatch.setattr(res, "_COSTLY_SECONDS", 6.5e-10 * 1000.0 * 300.0 * 300.0)
        assert res._svd_seconds(cfg(["probe_plain"]), costs[:1]) == one
        monkeypatch.setattr(res, "_COSTLY_SECONDS", 0.0)
        # two mirrors: one joint SVD of 1800 x 700, or the MAP's Cholesky
        joint = res._svd_seconds(cfg(["probe_plain", "probe_plain"]), costs)
        assert joint == pytest.approx(6.5e-10 * 1800 * 700 * 700, rel=1e-12)
        m, n = 1800.0, 700.0
        assert res._svd_seconds(cfg(["probe_plain", "probe_plain"], "map"), costs) == \
            pytest.approx(2e-11 * (2 * m * n * n + 4 / 3 * n ** 3), rel=1e-12)
        # a zonal mirror: no SVD at all
        assert res._svd_seconds(cfg(["probe_plain", "ideal"]), costs) == 0.0
        # the Gram rate from GRAM_MIN_BYTES on (8 B per entry), with a large-products kind
        big = cfg(["probe_plain", "probe_large"])
        entries = 1800.0 * 700.0
        monkeypatch.setattr(res, "GRAM_MIN_BYTES", 8.0 * entries)
        assert res._svd_seconds(big, costs) == pytest.approx(1.7e-10 * entries * 700,
                                                             rel=1e-12)
        monkeypatch.setattr(res, "GRAM_MIN_BYTES", 8.5 * entries)
        assert res._svd_seconds(big, costs) == pytest.approx(6.5e-10 * entries * 700,
                                                             rel=1e-12)
    finally:
        kinds.unregister_mirror_kind("probe_plain")
        kinds.unregister_mirror_kind("probe_large")


def test_the_set_up_seconds_add_the_mirrors_builds_and_the_reconstructor():
    config = presets.get("est-mcao")
    dx = config.telescope.diameter / config.telescope.n_pixels
    builds = sum(mirror_kind(d.kind).estimate(config, i, dx).setup_seconds
                 for i, d in enumerate(config.dms))
    est = res.estimate(config, 0.01)
    svd = res._svd_seconds(config, res._sensor_costs(config, len(plane_layout(config)), dx))
    assert builds > 1.0 and svd > 1.0
    assert est.setup_seconds == pytest.approx(builds + svd, rel=1e-12)


# ---------------------------------------------------------------- budget rules
def test_the_budget_streams_only_with_a_joint_reconstructor_and_large_products():
    assert res.budget_streams(presets.get("est-mcao"))
    assert not res.budget_streams(presets.get("dkist-scao"))  # one mirror
    assert not res.budget_streams(presets.get("kaos"))  # Zernike mirrors
    est = presets.get("est-mcao")
    zonal = est.replace(dms=(est.dms[0].__class__(**{**vars(est.dms[0]), "kind": "ideal",
                                                     "options": None}), *est.dms[1:]))
    assert not res.budget_streams(zonal)


def test_the_budget_streams_with_two_mirrors_and_one_of_large_products():
    from closedloop import kinds

    def plain_build(geometry, index):  # a mirror kind's build without `large_products`
        raise AssertionError("not built by the estimate")

    record = dataclasses.replace(mirror_kind("zernike"), name="probe_plain",
                                 build=plain_build)
    kinds.register_mirror_kind(record)
    try:
        def cfg(*names):
            return SimpleNamespace(dms=tuple(SimpleNamespace(kind=k) for k in names))

        assert res.budget_streams(cfg("actuators", "actuators"))
        assert res.budget_streams(cfg("probe_plain", "actuators"))
        assert res.budget_streams(cfg("zernike", "actuators", "zernike"))
        assert not res.budget_streams(cfg("probe_plain", "zernike"))
        assert not res.budget_streams(cfg("actuators"))
        assert not res.budget_streams(cfg("actuators", "ideal"))
    finally:
        kinds.unregister_mirror_kind("probe_plain")


def test_the_ideal_sensor_config_keeps_each_wfs_but_its_kind_and_noise():
    cfg = small("mcao3")
    ideal = res.ideal_sensor_config(cfg)
    assert len(ideal.wfss) == len(cfg.wfss)
    for w, v in zip(cfg.wfss, ideal.wfss, strict=True):
        assert (v.kind, v.noise) == ("ideal", 0.0)
        assert (v.altitude, v.field_of_view, v.n_subapertures, v.field_samples, v.dm) == (
            w.altitude, w.field_of_view, w.n_subapertures, w.field_samples, w.dm)
    assert ideal.dms == cfg.dms and ideal.layers == cfg.layers and ideal.loop == cfg.loop


# ---------------------------------------------------------------- refusals
def test_a_run_past_the_limit_names_the_largest_part_its_driver_and_the_limit():
    cfg = small()
    est = res.estimate(cfg, 0.05)
    limit = est.peak_bytes * 0.99
    part = est.largest
    msg = (f"this run needs about {format_size(est.peak_bytes)} of memory, more than "
           f"{format_size(limit)} (the limit given); the largest part, {part} "
           f"({format_size(est.parts[part])}), is driven by `{est.drivers[part]}`: reduce it "
           f"(see `closedloop config --estimate`).")
    with pytest.raises(res.ResourceError, match="^" + re.escape(msg) + "$"):
        res.check_resources(cfg, 0.05, limit=limit)
    assert res.check_resources(cfg, 0.05, limit=est.peak_bytes) == est  # at the limit: runs


def test_the_default_limit_is_half_the_available_memory(monkeypatch):
    cfg = small()
    est = res.estimate(cfg, 0.05)
    monkeypatch.setattr(res, "available_memory", lambda: est.peak_bytes * 2.0)
    assert res.check_resources(cfg, 0.05).peak_bytes == est.peak_bytes
    monkeypatch.setattr(res, "available_memory", lambda: est.peak_bytes * 1.98)
    avail = format_size(est.peak_bytes * 1.98)
    with pytest.raises(res.ResourceError, match=re.escape(
            f"more than {format_size(est.peak_bytes * 0.99)} (50% of the {avail} available)")):
        res.check_resources(cfg, 0.05)


def test_without_the_set_up_the_run_s_kept_parts_are_checked():
    cfg = small()
    est = res.estimate(cfg, 0.05, budget=False)
    need = res.BASELINE_BYTES + est.run_bytes
    assert est.peak_bytes > need and est.largest not in res._RUN_PARTS  # the set-up peaks
    assert res.check_resources(cfg, 0.05, setup=False, limit=need) == est
    part = max((k for k in res._RUN_PARTS if k in est.parts), key=est.parts.__getitem__)
    with pytest.raises(res.ResourceError, match=re.escape(
            f"needs about {format_size(need)} of memory") + ".*" + re.escape(
            f"the largest part, {part} ({format_size(est.parts[part])})")):
        res.check_resources(cfg, 0.05, setup=False, limit=need - 1.0)  # above the baseline


def test_the_oracle_s_second_atmosphere_is_counted_in_the_check():
    cfg = small()
    plain, oracle = res.estimate(cfg, 0.05), res.estimate(cfg, 0.05, oracle=True)
    assert oracle.peak_bytes > plain.peak_bytes
    limit = (plain.peak_bytes + oracle.peak_bytes) / 2
    assert res.check_resources(cfg, 0.05, limit=limit) == plain
    with pytest.raises(res.ResourceError, match=re.escape(format_size(oracle.peak_bytes))):
        res.check_resources(cfg, 0.05, oracle=True, limit=limit)


def test_a_budget_too_large_is_refused_with_its_own_advice():
    config = presets.get("dkist-scao")
    est = res.estimate(config, 0.05, budget=True)
    assert est.largest == "budget"
    with pytest.raises(res.ResourceError, match=re.escape(
            "is driven by `budget_every`: run without the error budget (no `budget_every`: "
            "its model of ideal sensors measures every pixel of the mirrors' discs) (see "
            "`closedloop config --estimate`).") + "$"):
        res.check_resources(config, 0.05, budget=True, limit=est.peak_bytes / 2)


@pytest.mark.parametrize(("limit", "kind", "msg"), [
    # validation.check_real's words and types (left26-twins)
    (0, ValueError, "`memory_limit` must be > 0.0; got 0.0."),
    (-1.0, ValueError, "`memory_limit` must be > 0.0; got -1.0."),
    (float("nan"), ValueError, "`memory_limit` must be finite; got nan."),
    (True, TypeError, "`memory_limit` must be a real number; got True."),
    (np.array(True), TypeError, "`memory_limit` must be a real number; got True."),
    ("1e9", TypeError, "`memory_limit` must be a real number; got '1e9'."),
    (None.__class__, TypeError, "`memory_limit` must be a real number; got <class 'NoneType'>."),
])
def test_a_limit_that_is_no_positive_number_is_refused(limit, kind, msg):
    with pytest.raises(kind, match="^" + re.escape(msg) + "$"):
        res.check_resources(small(), 0.05, limit=limit)


@pytest.mark.parametrize("wrap", [np.array, np.int64, np.float32])
def test_a_limit_as_a_numpy_number_is_its_value(wrap):
    # a 0-d array or NumPy number is its value (left26-twins): refused before as
    # "must be a number of bytes"; 1 byte is a limit every run exceeds, 1e15 none does
    with pytest.raises(res.ResourceError, match=r"more than 1 B "):
        res.check_resources(small(), 0.05, limit=wrap(1))
    assert res.check_resources(small(), 0.05, limit=wrap(10**15)).peak_bytes > 0



def test_a_limit_under_one_byte_is_a_limit():
    with pytest.raises(res.ResourceError, match=r"^this run needs about .* more than 0 B "):
        res.check_resources(small(), 0.05, limit=0.5)


def test_a_long_run_of_image_formation_is_refused_naming_its_key(monkeypatch):
    cfg = small()
    # a sensor that forms images for 1.5 s a frame: 2400 frames are 1 h (allowed), 2401
    # frames more than 1 h (refused)
    costly = SensorCost(10.0, 10.0, 1.5, "wfss[0].image_formation")
    pixels = []

    def costs(config, n, dx):
        pixels.append(dx)
        return [costly, costly]

    monkeypatch.setattr(res, "_sensor_costs", costs)
    dt = cfg.loop.time_step
    res.check_resources(cfg, 1200 * dt, limit=1e30)
    frames = 1201
    msg = (f"this run forms and correlates images for about "
           f"{3.0 * frames / 3600:.1f} h (3 s per frame, {frames} frames), more than 1 h; it "
           f"is driven by `wfss[0].image_formation`: set it to false (the linear sensor) or "
           f"shorten `duration`.")
    with pytest.raises(res.ResourceError, match="^" + re.escape(msg) + "$"):
        res.check_resources(cfg, frames * dt, limit=1e30)
    # the pupil pixel the sensors are costed at: D / N
    assert set(pixels) == {cfg.telescope.diameter / cfg.telescope.n_pixels}
    # 1000 s a frame for 36,000 frames: 10,000 h
    costly = SensorCost(10.0, 10.0, 500.0, "wfss[0].image_formation")
    with pytest.raises(res.ResourceError, match=re.escape(
            "for about 10000.0 h (1e+03 s per frame, 36000 frames)")):
        res.check_resources(cfg, 36000 * dt, limit=1e30)


def test_available_memory_is_the_common_helper_s():
    from modalinfo.common.memory import available_memory_bytes

    assert res.available_memory() == available_memory_bytes()
