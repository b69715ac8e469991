"""SimulationResult's views and file on results built by hand, against laws written here.

References (outside the code): residual-variance histories built here with a known loop
closure (a step with deterministic ripple and dips placed around the 5-ms window, so the
closure frame is known by construction); the Marechal law ``SR = exp(-sigma^2)``;
numpy means over the frames from the known closure; the area of the region where a
bilinear interpolation of a 3x3 map exceeds a threshold, integrated analytically
(``4 (3/4 - ln(4) / 4)`` cells for a centre at 0.9 and edges at 0.1, threshold 0.3);
a sinusoid's frequency for the Welch spectrum; the error budget's sum and table written
out; a save/load round trip compared field by field, and a file damaged here with h5py.
Fast (no simulation): the tests of closedloop/result.py that mutation testing runs.
"""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.result import ErrorBudget, SimulationResult, UncheckedResultWarning, marechal_note
from modalinfo.telemetry import ModalLog

T = 1e-3  # frame [s]: the 5-ms window of the closure detection is 5 frames


def _config(time_step=T, closed=True, n_points=3, size=60.0):
    return SimulationConfig(
        telescope=TelescopeConfig(diameter=1.0, n_pixels=8),
        layers=(LayerConfig(altitude=0.0, d_over_r0=5.0, wind_speed=10.0),),
        dms=(DMConfig(altitude=0.0, n_modes=2),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=2, field_samples=1),),
        loop=LoopConfig(time_step=time_step, integration_time=time_step,
                        delay=time_step / 2, closed=closed),
        field=FieldConfig(size=size, n_points=n_points))


def _result(variance, config=None, **extra):
    """A result whose every direction has the history ``variance`` (T,) or (T, n_dir)."""
    config = config or _config()
    v = np.asarray(variance, dtype=float)
    n_dir = config.field.n_points ** 2
    if v.ndim == 1:
        v = v[:, None] * np.ones((1, n_dir))
    times = (np.arange(v.shape[0]) + 1) * config.loop.time_step
    return SimulationResult(config=config, seed=3, predictor="none", times=times,
                            directions=np.zeros((n_dir, 2)), residual_variance=v,
                            elapsed=extra.pop("elapsed", 0.5), version="test", **extra)


def _step(n=200, k0=20, dips=(), open_level=2.0):
    """Open-loop level until ``k0``, then 0.2 rad^2 with a +-0.01 ripple, dips at ``dips``."""
    v = 0.2 + 0.01 * (-1.0) ** np.arange(n)
    v[:k0] = open_level
    v[list(dips)] = open_level
    return v


def test_marechal_strehl_peak_and_map_orientation():
    v = np.array([[0.1 * (k + 1) + 0.01 * j for j in range(9)] for k in range(12)])
    r = _result(v)
    np.testing.assert_array_equal(r.strehl, np.exp(-v))
    np.testing.assert_array_equal(r.strehl_peak, np.exp(-v[:, 0]))
    smap = r.strehl_map(after_closure=False)
    assert smap.shape == (3, 3)
    # directions row-major over the grid: y rows, x columns
    np.testing.assert_allclose(smap, np.exp(-v).mean(axis=0).reshape(3, 3), rtol=1e-15)
    np.testing.assert_allclose(r.strehl_map(start=4), np.exp(-v[4:]).mean(axis=0).reshape(3, 3),
                               rtol=1e-15)
    assert r.steps_per_second == 12 / 0.5
    assert math.isnan(_result(v, elapsed=0.0).steps_per_second)
    assert r.field_shape == (3, 3)


@pytest.mark.parametrize("dips,closure", [
    ((), 20),
    ((24,), 25),          # 4 steady frames, a dip: the 5-frame window starts after it
    ((24, 30), 25),       # 25..29 hold 5 frames: a later dip is turbulence
    ((24, 29), 30),       # 25..28 hold only 4
])
def test_closure_is_the_first_frame_holding_5_ms(dips, closure):
    r = _result(_step(dips=dips))
    assert r.closure_index == closure
    assert r.closure_time == pytest.approx((closure + 1) * T, rel=1e-12)
    assert r.loop_status == "closed" and r.closed and not r.diverged
    s = r.summary()
    peak = np.exp(-_step(dips=dips))
    assert s["strehl_peak_mean"] == pytest.approx(peak[closure:].mean(), rel=1e-12)
    assert s["strehl_field_mean"] == pytest.approx(peak[closure:].mean(), rel=1e-12)
    assert s["closure_time_s"] == r.closure_time
    assert (s["frames"], s["seed"], s["predictor"], s["open_loop"]) == (200, 3, "none", False)
    assert s["loop_status"] == "closed" and s["closed"] and not s["diverged"]
    assert s["steps_per_second"] == 400.0


def test_closure_window_follows_the_frame_period():
    # 0.5-ms frames: 5 ms is 10 frames; a dip 9 frames after the step moves the closure
    cfg = _config(time_step=0.5e-3)
    assert _result(_step(dips=(29,)), cfg).closure_index == 30
    assert _result(_step(dips=(30,)), cfg).closure_index == 20
    # 2.5-ms frames: the window is at least 3 frames (not round(5 / 2.5) = 2)
    cfg = _config(time_step=2.5e-3)
    assert _result(_step(dips=(22,)), cfg).closure_index == 23
    assert _result(_step(dips=(23,)), cfg).closure_index == 20


def test_open_loop_and_short_runs_claim_no_closure():
    r = _result(_step(), _config(closed=False))
    assert r.open_loop and r.closure_index == 0 and r.loop_status == "open loop"
    s = r.summary()
    assert math.isnan(s["closure_time_s"]) and s["open_loop"] and not s["closed"]
    assert s["strehl_peak_mean"] == pytest.approx(np.exp(-_step()).mean(), rel=1e-12)
    assert _result([2.0, 0.2, 0.2]).closure_index == 0
    status = _result([2.0, 0.2, 0.2]).loop_status
    assert status == ("did not close: 3 frames are too few to detect the loop closure (it "
                      "needs 10: twice the 5-ms window)")


def test_statuses_of_loops_that_did_not_close_or_diverged():
    v = _step()
    v[150] = np.nan
    assert _result(v).loop_status == "diverged: the residual is not finite from frame 150"
    # last quarter: 2 + 6 i / 98 for i = 74..98, mean 2 + 6 * 86 / 98 = 7.265 rad^2
    grow = np.concatenate([[2.0], np.linspace(2.0, 8.0, 99)])
    assert _result(grow).loop_status == (
        "diverged: the residual at the end (7.27 rad^2, field mean) is 3.6 times the "
        "open-loop level (2 rad^2)")
    drop_then_grow = np.concatenate([[2.0], np.full(20, 0.1), np.full(79, 0.9)])
    assert _result(drop_then_grow).loop_status == (
        "diverged: the residual grew to 9.0 times its lowest 5-ms mean (0.9 against 0.1 "
        "rad^2, field mean)")
    # a step late in the run: the band of the second half holds from the step only
    late = _step(k0=120)
    r = _result(late)
    assert r.closure_index == 100 and not r.closed
    assert r.loop_status == ("did not close: the SR peak reaches no steady state in the "
                             "first half of the run")
    s = r.summary()
    assert math.isnan(s["closure_time_s"])
    assert s["strehl_peak_mean"] == pytest.approx(np.exp(-late[100:]).mean(), rel=1e-12)
    # never rose: a closure "found" at frame 0, before any command
    flat = 0.2 + 0.01 * (-1.0) ** np.arange(100)
    assert _result(flat).loop_status.startswith("did not close: the SR peak (0.819 in the "
                                                "second half) never rose clearly")
    # rose, but the residual stays above half the open-loop level
    half = _step(open_level=0.3)
    assert _result(half).loop_status == (
        "did not close: the residual (0.2 rad^2, field mean) stays above half the "
        "open-loop level (0.3 rad^2)")


def test_corrected_field_of_a_bilinear_map():
    # centre 0.9, edges 0.1 on a 3x3 grid of 60": in each 30" cell the bilinear SR exceeds
    # 0.3 where (1 - u)(1 - v) > 1/4: area 3/4 - ln(4)/4 of the cell
    sr = np.full((3, 3), 0.1)
    sr[1, 1] = 0.9
    r = _result(np.tile(-np.log(sr).ravel(), (12, 1)))
    area = 4 * (0.75 - math.log(4.0) / 4) * 30.0 ** 2
    exact = 2 * math.sqrt(area / math.pi) / 60.0
    assert r.corrected_fov_diameter(0.3, refine=256, start=0) == pytest.approx(exact, rel=2e-3)
    assert r.corrected_fov_diameter(0.3, start=0) == pytest.approx(exact, rel=3e-2)
    # everywhere above: the whole 60" square; nowhere: 0; one direction: NaN (a point
    # measures no area; issue 27: it was reported as a corrected field of 0.00')
    full = _result(np.full((12, 9), 0.05))
    assert full.corrected_fov_diameter(start=0) == pytest.approx(
        2 * math.sqrt(60.0 ** 2 / math.pi) / 60.0, rel=1e-12)
    assert _result(np.full((12, 9), 3.0)).corrected_fov_diameter(start=0) == 0.0
    one = _result(np.full((12, 1), 0.05), _config(n_points=1, size=0.0))
    assert math.isnan(one.corrected_fov_diameter(start=0))
    for bad in (0.0, 1.0, -0.1):
        with pytest.raises(ValueError, match=rf"^`threshold` must be in \(0, 1\); got {bad}"):
            r.corrected_fov_diameter(bad)


def test_start_must_be_a_frame_of_the_run():
    r = _result(_step(n=30, k0=5))
    for bad in (-1, 30, True, 2.0, None.__class__):
        with pytest.raises(ValueError, match=r"^`start` must be a frame index in \[0, 30\)"):
            r.strehl_map(start=bad)
    assert r.strehl_map(start=29).shape == (3, 3)
    np.testing.assert_array_equal(r.strehl_map(start=np.int64(0)),
                                  r.strehl_map(after_closure=False))


def test_spectrum_of_the_sr_peak_finds_a_sinusoid():
    n = 512
    v = 0.2 + 0.05 * np.sin(2 * np.pi * 125.0 * T * np.arange(n))
    v[:10] = 2.0
    r = _result(v)
    freqs, psd = r.strehl_peak_spectrum(start=10)
    assert freqs[-1] == 500.0 and freqs.size == 129  # nperseg 256 by default
    assert freqs[np.argmax(psd)] == 125.0
    freqs, _ = r.strehl_peak_spectrum(nperseg=64, start=10)
    assert freqs.size == 33


def _budget(n_dir=9):
    d = np.arange(n_dir, dtype=float)
    return ErrorBudget(directions=np.column_stack([d, -d]), fitting=0.1 + d, aliasing=0.2 + d,
                       temporal=0.3 + d, noise=0.4 + d, measured=2.0 + 4 * d,
                       frames=np.arange(3))


def test_error_budget_sum_ratio_and_table():
    b = _budget()
    np.testing.assert_allclose(b.total, 1.0 + 4 * np.arange(9), rtol=1e-15)
    np.testing.assert_allclose(b.ratio, (1.0 + 4 * np.arange(9)) / (2.0 + 4 * np.arange(9)),
                               rtol=1e-15)
    lines = b.table().splitlines()
    assert lines[0] == ("      x      y  fitting aliasing temporal   noise     sum measured"
                        " sum/meas")
    assert lines[2] == "    1.0   -1.0    1.100    1.200    1.300   1.400   5.000    6.000    0.833"
    assert len(lines) == 10


def _full_result():
    rng = np.random.default_rng(1)
    cfg = _config()
    # Z4, Z5 (not the default Z2, Z3) and one log of named modes
    logs = {f"dm0.{q}": ModalLog(rng.standard_normal((40, 2)), rate=1e3, modes=[4, 5],
                                 wavelength=500e-9, start_time=T, metadata={"quantity": q})
            for q in ("residual", "pol", "commands")}
    logs["dm1.named"] = ModalLog(rng.standard_normal((40, 2)), rate=1e3, modes=["a", "b"],
                                 convention="labels", wavelength=500e-9, start_time=T)
    return _result(_step(n=40, k0=5), cfg, logs=logs, snapshots=rng.standard_normal((2, 1, 8, 8)),
                   snapshot_directions=np.zeros((1, 2)),
                   measurements=[rng.standard_normal((40, 8))], budget=_budget())


def test_save_load_round_trip_of_every_field(tmp_path):
    r = _full_result()
    path = r.save(tmp_path / "r.h5")
    back = SimulationResult.load(path)
    for name in ("times", "directions", "residual_variance", "snapshots",
                 "snapshot_directions"):
        np.testing.assert_array_equal(getattr(back, name), getattr(r, name))
    assert (back.config, back.seed, back.predictor, back.elapsed, back.version) == (
        r.config, 3, "none", 0.5, "test")
    assert len(back.measurements) == 1
    np.testing.assert_array_equal(back.measurements[0], r.measurements[0])
    for f in ("directions", "fitting", "aliasing", "temporal", "noise", "measured", "frames"):
        np.testing.assert_array_equal(getattr(back.budget, f), getattr(r.budget, f))
    for name, log in r.logs.items():
        np.testing.assert_array_equal(back.logs[name].coeffs, log.coeffs)
        assert back.logs[name].metadata == log.metadata and back.logs[name].rate == 1e3
    with pytest.raises(FileExistsError):
        r.save(path)
    _result(_step(n=12, k0=2)).save(path, overwrite=True)
    lean = SimulationResult.load(path)
    assert lean.snapshots is None and lean.budget is None and lean.measurements == []
    assert lean.logs == {}


def test_damage_is_refused_and_foreign_files_named(tmp_path):
    path = _full_result().save(tmp_path / "r.h5")
    good = path.read_bytes()
    for name in ("snapshots", "snapshot_directions", "budget/frames", "measurements/wfs0",
                 "residual_variance", "logs/dm0.pol/modalinfo_header"):
        path.write_bytes(good)
        with h5py.File(path, "r+") as f:
            d = f[name]
            d[(0,) * d.ndim] = d[(0,) * d.ndim] + 1
        with pytest.raises(ValueError, match=f"^corrupt closedloop result '{path}': dataset "
                           f"'{name}' does not match its SHA-256 checksum$"):
            SimulationResult.load(path)
    path.write_bytes(good)
    with h5py.File(path, "r+") as f:
        del f["budget/noise"], f["snapshots"]
    with pytest.raises(ValueError, match=r"datasets 'budget/noise', 'snapshots' are missing$"):
        SimulationResult.load(path)
    path.write_bytes(good)
    with h5py.File(path, "r+") as f:
        f["a"], f["b"] = [1.0], [2.0]
    with pytest.raises(ValueError, match=r"datasets 'a', 'b' were added after the file was "
                       r"written \(no checksums\)$"):
        SimulationResult.load(path)
    for attr, value in (("elapsed", 0.25), ("predictor", "arma"), ("version", "x"),
                        ("format_version", 4)):
        path.write_bytes(good)
        with h5py.File(path, "r+") as f:
            f.attrs[attr] = value
        with pytest.raises(ValueError, match=r"the attributes \(version, seed, predictor, "
                           r"elapsed, config\) do not match their SHA-256 checksum$"):
            SimulationResult.load(path)
    path.write_bytes(good)
    with h5py.File(path, "r+") as f:
        f.attrs["sha256"] = np.bytes_(b"{}")
    with pytest.raises(ValueError, match=r"its checksums \(attribute 'sha256'\) are missing "
                       "or unreadable$"):
        SimulationResult.load(path)
    with h5py.File(path, "r+") as f:
        del f.attrs["sha256"]
        f.attrs["format_version"] = 2
    with pytest.warns(UncheckedResultWarning, match=f"^'{path}': a format-2 closedloop result"):
        SimulationResult.load(path)
    with pytest.raises(FileNotFoundError, match="result file '.*none.h5' does not exist"):
        SimulationResult.load(tmp_path / "none.h5")
    (tmp_path / "text.h5").write_text("not hdf5")
    with pytest.raises(ValueError, match="text.h5': not an HDF5 closedloop result"):
        SimulationResult.load(tmp_path / "text.h5")
    with h5py.File(tmp_path / "other.h5", "w") as f:
        f["x"] = [1.0]
    with pytest.raises(ValueError, match="other.h5': not a closedloop result "
                       r"\(no format='closedloop-result'\)"):
        SimulationResult.load(tmp_path / "other.h5")


def test_default_start_is_the_closure_and_summary_of_a_diverged_run():
    v = _step(dips=(24,))
    r = _result(v)
    np.testing.assert_allclose(r.strehl_map(), np.exp(-v[25:]).mean() * np.ones((3, 3)),
                               rtol=1e-12)
    np.testing.assert_allclose(r.strehl_map(after_closure=False, start=4),
                               np.exp(-v[4:]).mean() * np.ones((3, 3)), rtol=1e-12)
    # diverged: the numbers of the second half, each direction its own scale
    base = np.concatenate([[2.0], np.full(20, 0.1), np.full(79, 0.9)])
    scale = np.linspace(0.5, 2.0, 9)
    r = _result(base[:, None] * scale[None, :])
    s = r.summary()
    assert s["diverged"] and not s["closed"] and math.isnan(s["closure_time_s"])
    assert r.closure_index == 1
    assert s["strehl_peak_mean"] == pytest.approx(math.exp(-0.45), rel=1e-12)
    assert s["strehl_field_mean"] == pytest.approx(np.exp(-0.9 * scale).mean(), rel=1e-12)
    fov = s["corrected_fov_diameter_arcmin"]
    assert fov == r.corrected_fov_diameter(start=50) != r.corrected_fov_diameter(start=1)


def test_corrected_field_weights_on_the_grid_nodes():
    # refine=1: the 3x3 nodes themselves, each owning a 30" cell; edge nodes half of it
    # along the edge's normal, corners a quarter (trapezoid weights)
    cell = 30.0 ** 2
    for column, owned in ((1, 2.0), (0, 1.0), (2, 1.0)):  # centre column: 1/2 + 1 + 1/2
        sr = np.full((3, 3), 0.1)
        sr[:, column] = 0.9
        r = _result(np.tile(-np.log(sr).ravel(), (12, 1)))
        expected = 2 * math.sqrt(owned * cell / math.pi) / 60.0
        assert r.corrected_fov_diameter(0.3, refine=1, start=0) == pytest.approx(expected,
                                                                                 rel=1e-12)
    sr = np.full((3, 3), 0.1)
    sr[1, 1] = 0.9
    r = _result(np.tile(-np.log(sr).ravel(), (12, 1)))
    assert r.corrected_fov_diameter(0.3, refine=1, start=0) == pytest.approx(
        2 * math.sqrt(cell / math.pi) / 60.0, rel=1e-12)
    # the documented default refinement is 16
    assert r.corrected_fov_diameter(start=0) == r.corrected_fov_diameter(refine=16, start=0)
    # the map averaged from `start`: bright first half, dark second half
    v = np.vstack([np.full((6, 9), 0.05), np.full((6, 9), 3.0)])
    two = _result(v)
    assert two.corrected_fov_diameter(start=6) == 0.0
    assert two.corrected_fov_diameter(start=0) > 1.0


def test_spectrum_starts_at_start():
    r = _result(_step(n=100, k0=10))
    assert r.strehl_peak_spectrum(start=50)[0].size == 26  # 50 samples: 26 frequencies
    assert r.strehl_peak_spectrum()[0].size == 46  # from the closure, frame 10: 90 samples


def test_a_step_at_mid_run_closes_there_and_an_odd_run_is_checked_at_its_middle():
    r = _result(_step(k0=100))
    assert r.closure_index == 100 and r.loop_status == "closed"
    # 201 frames, step at 121: the fallback frame 100 is before it, no steady state
    r = _result(_step(n=201, k0=121))
    assert r.closure_index == 100
    assert r.loop_status == ("did not close: the SR peak reaches no steady state in the "
                             "first half of the run")


def _format_1(path, result):
    """Rewrite a saved result in the format-1 layout (bare log datasets, JSON attributes)."""
    import json

    with h5py.File(path, "r+") as f:
        del f.attrs["sha256"]
        f.attrs["format_version"] = 1
        del f["logs"]
        g = f.create_group("logs")
        for name, log in result.logs.items():
            d = g.create_dataset(name, data=np.asarray(log.coeffs))
            d.attrs["modes"] = json.dumps(list(log.modes))
            d.attrs["metadata"] = json.dumps(log.metadata)
            d.attrs["rate"] = log.rate
            d.attrs["start_time"] = float(log.times[0])
            d.attrs["wavelength"] = log.wavelength


def test_old_files_load_with_a_warning(tmp_path):
    r = _full_result()
    path = r.save(tmp_path / "old.h5")
    _format_1(path, r)
    with pytest.warns(UncheckedResultWarning) as caught:
        back = SimulationResult.load(path)
    assert str(caught[0].message) == (
        f"'{path}': a format-1 closedloop result, written before results carried checksums: "
        "its datasets are not verified (saving it again adds them)")
    for name, log in r.logs.items():
        got = back.logs[name]
        np.testing.assert_array_equal(got.coeffs, log.coeffs)
        assert (got.modes, got.rate, got.wavelength, got.metadata, got.units) == (
            log.modes, 1e3, 500e-9, log.metadata, "rad")
        assert got.convention == log.convention and got.times[0] == T
    assert back.logs["dm1.named"].convention == "labels"
    assert back.logs["dm0.pol"].convention == "noll" and back.logs["dm0.pol"].modes == [4, 5]
    # the oldest files: no format_version, no measurements
    with h5py.File(path, "r+") as f:
        del f.attrs["format_version"], f["measurements"]
    with pytest.warns(UncheckedResultWarning, match="a format-1 closedloop result"):
        assert SimulationResult.load(path).measurements == []


def test_log_coefficients_are_checked_by_their_own_header(tmp_path):
    r = _full_result()
    logs = dict(r.logs)
    logs["dm0.timed"] = ModalLog(np.ones((40, 2)), timestamps=np.arange(40) * T + T,
                                 modes=[2, 3], wavelength=500e-9)
    path = _result(_step(n=40, k0=5), r.config, logs=logs).save(tmp_path / "r.h5")
    good = path.read_bytes()
    for name in ("logs/dm0.pol/coefficients", "logs/dm0.timed/timestamps"):
        path.write_bytes(good)
        with h5py.File(path, "r+") as f:
            f[name][0] = f[name][0] + 1
        what = name.rsplit("/", 1)[1]
        with pytest.raises(ValueError, match=rf"^corrupt HDF5 file '{path}': {what} do not "
                           "match their SHA-256 checksum$"):
            SimulationResult.load(path)


def test_whole_messages_singular_and_plural(tmp_path):
    path = _full_result().save(tmp_path / "r.h5")
    good = path.read_bytes()
    head = f"corrupt closedloop result '{path}': "
    cases = [
        (lambda f: f["times"].__setitem__(0, 5.0) or f["directions"].__setitem__(0, 5.0),
         "datasets 'directions', 'times' do not match their SHA-256 checksums"),
        (lambda f: f.__delitem__("times"), "dataset 'times' is missing"),
        (lambda f: f.create_dataset("x", data=[1.0]),
         "dataset 'x' was added after the file was written (no checksum)"),
    ]
    for damage, message in cases:
        path.write_bytes(good)
        with h5py.File(path, "r+") as f:
            damage(f)
        with pytest.raises(ValueError) as info:
            SimulationResult.load(path)
        assert str(info.value) == head + message


@pytest.mark.parametrize("sigmas,closure", [(3.5, 25), (2.5, 20)])
def test_band_floor_is_three_robust_sigmas_below_the_median(sigmas, closure):
    # the documented band, from the second half (written here): median - 3 x 1.4826 MAD;
    # a dip in the first half at `sigmas` below the median is outside it (3.5) or not (2.5)
    v = _step()
    tail = np.exp(-v[100:])
    med = np.median(tail)
    sigma = 1.4826 * np.median(np.abs(tail - med))
    v[24] = -math.log(med - sigmas * sigma)
    assert _result(v).closure_index == closure


def test_from_run_assembles_the_documented_logs():
    from importlib.metadata import version

    from closedloop import LoopModel

    base = _config()
    cfg = base.replace(
        dms=(base.dms[0], DMConfig(altitude=0.0, kind="ideal")),
        wfss=(base.wfss[0], WFSConfig(altitude=0.0, field_of_view=0.0, kind="ideal",
                                      field_samples=1, dm=1)))
    model = LoopModel(cfg)
    widths = [sl.stop - sl.start for sl in model.mode_slices]
    n, m = 6, sum(widths)
    rng = np.random.default_rng(2)
    arrays = {q: rng.standard_normal((n, m)) for q in ("measured", "pol", "commands")}
    variance = rng.random((n, 9))
    meas = [rng.standard_normal((n, 8))]
    snaps, snap_dirs = rng.standard_normal((2, 1, 8, 8)), np.zeros((1, 2))
    r = SimulationResult.from_run(config=cfg, seed=11, model=model, variance=variance,
                                  elapsed=0.25, predictor_name="arma", measurements=meas,
                                  snapshots=snaps, snapshot_directions=snap_dirs, **arrays)
    assert r.config == cfg and r.snapshots is snaps and r.snapshot_directions is snap_dirs
    np.testing.assert_array_equal(r.times, (np.arange(n) + 1) * T)
    np.testing.assert_array_equal(r.directions, np.array(model.geometry.directions))
    assert r.residual_variance is variance and r.measurements[0] is meas[0]
    assert (r.seed, r.predictor, r.elapsed, r.version) == (11, "arma", 0.25,
                                                           version("modalinfo"))
    assert sorted(r.logs) == sorted(f"dm{i}.{q}" for i in range(2)
                                    for q in ("residual", "pol", "commands"))
    for i, dm in enumerate(model.dms):
        sl = model.mode_slices[i]
        for q, key in (("residual", "measured"), ("pol", "pol"), ("commands", "commands")):
            log = r.logs[f"dm{i}.{q}"]
            np.testing.assert_array_equal(log.coeffs, arrays[key][:, sl])
            assert log.coeffs.flags.c_contiguous
            assert (log.rate, log.units, log.wavelength, log.times[0]) == (
                1e3, "rad", 500e-9, T)
            assert log.convention == ("noll" if i == 0 else "labels")
            assert list(log.modes) == ([2, 3] if i == 0 else list(dm.labels))
            assert log.metadata == {
                "source": "closedloop", "dm": i, "dm_altitude_m": 0.0,
                "dm_diameter_m": dm.diameter, "predictor": "arma", "seed": 11,
                "config": cfg.to_dict(), "quantity": q}


def test_error_budget_table_explains_a_negative_term():
    # aliasing < 0 in direction 1 of 3 (the axis is direction 0, at (0, 0)); the note
    # gives fitting + aliasing on axis / over the field, written out here
    b = ErrorBudget(directions=np.array([[0.0, 0.0], [30.0, 0.0], [0.0, 30.0]]),
                    fitting=np.array([0.5, 0.8, 0.6]), aliasing=np.array([0.1, -0.3, 0.2]),
                    temporal=np.array([0.1, 0.1, 0.1]), noise=np.zeros(3),
                    measured=np.array([0.7, 0.6, 0.9]), frames=np.arange(3))
    lines = b.table().splitlines()
    assert len(lines) == 5  # header, three rows, the note
    assert lines[-1].startswith("note: aliasing < 0 in 1 of 3 directions (min -0.3): ")
    assert "is a variance: 0.6 / 0.633 " in lines[-1]  # (0.6, 0.5, 0.8): mean 1.9 / 3
    assert lines[-1] == "note: " + b.sign_note()
    assert "note" not in _budget().table()  # every term >= 0: no note


def test_fov_threshold_of_the_wrong_type_is_named():
    r = _result(_step(n=40, k0=5), _config())
    with pytest.raises(TypeError, match=r"`threshold` must be a real number; got '0.3'"):
        r.corrected_fov_diameter("0.3")
    with pytest.raises(TypeError, match=r"`after_closure` must be a bool; got 'no'"):
        r.strehl_map(after_closure="no")  # a true string: the window after closure was used


def test_marechal_note_below_the_validated_strehl():
    # test_physics checks exp(-sigma^2) against the FFT-PSF Strehl within 0.05 only where
    # SR > 0.3 (sigma^2 < 1.2 rad^2): a caveat below, none above, none for a NaN
    assert marechal_note(math.exp(-1.3)).startswith("SR = exp(-sigma^2) (Marechal) is below 0.3")
    assert marechal_note(math.exp(-1.1)) == "" and marechal_note(float("nan")) == ""
    # a run's line carries it: residual 2 rad^2 after closure (SR 0.135)
    from closedloop.cli import _summary_line

    low = _result(np.r_[np.full(10, 20.0), np.full(30, 2.0)], _config())
    high = _result(np.r_[np.full(10, 20.0), np.full(30, 0.2)], _config())
    assert _summary_line(low).endswith("; note: " + marechal_note(math.exp(-2.0)))
    assert "note" not in _summary_line(high)


def test_error_budget_of_no_residual_has_no_ratio():
    # zero turbulence: every term and the measured residual 0; 0 / 0 has no value (NaN,
    # shown "nan" in the table), without NumPy's RuntimeWarning (an error in this suite)
    zero = np.zeros(1)
    b = ErrorBudget(directions=np.zeros((1, 2)), fitting=zero, aliasing=zero, temporal=zero,
                    noise=zero, measured=zero, frames=np.arange(3))
    assert np.isnan(b.ratio).all()
    assert b.table().splitlines()[1].endswith("nan")
