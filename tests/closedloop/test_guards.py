"""Guard rails: meaningless configs refused, loops that did not close said so, resources.

References (outside the code under test):
- sampling rules written out here: a Zernike of radial order n (Noll's (n+1)(n+2)/2
  modes up to order n) needs 2 pixels per cycle across its disc, a subaperture 2 pixels;
  the disc of a DM conjugated at h with a field theta is D + 2 h tan(theta / 2);
- loop states of residual-variance histories built here by hand (a drop to a floor, an
  exponential growth, no correction, too few frames, a NaN), and of real runs whose
  fate follows from the control law: a forecast 3 times the POL ``p = m + s`` (``s``
  the commands seen) gives ``c_k = c_{k-1} + g (3 m + 2 s)``, and with ``s ~ c_{k-1}``
  the commands grow by ``1 + 2 g = 2`` per frame; a gain of 1e-4 corrects nothing in
  40 frames;
- memory: the byte count of the arrays a config implies, computed here by hand (a layer
  screen G**2 float64, logs frames x columns float64), and refusal past a limit.
"""

import math

import numpy as np
import pytest

from closedloop import simulate
from closedloop.config import LayerConfig, SimulationConfig
from closedloop.optics.geometry import ARCSEC
from closedloop.resources import ResourceError, check_resources, estimate
from closedloop.result import SimulationResult
from modalinfo.forecast import PersistencePredictor

from .conftest import small, with_values


# ---------------------------------------------------------------- physical sense
def test_modes_beyond_the_pupil_sampling_are_refused():
    # 16 x 16 subapertures on the upper DM (416 slopes), so that the pupil sampling, not
    # the measurements (test_physics_guards.py), bounds its modes here
    cfg = with_values(small(), "wfss", 1, n_subapertures=16)
    # upper DM: disc D + 2 h tan(fov / 2) at 32 pixels per 4 m
    fov = cfg.wfss[1].field_of_view
    across = (4.0 + 2 * 10_000 * math.tan(fov / 2 * ARCSEC)) / (4.0 / 32)
    n_max = int(across // 2)
    limit = (n_max + 1) * (n_max + 2) // 2 - 1  # modes Z2 .. up to radial order n_max
    with_values(cfg, "dms", 1, n_modes=limit)  # the largest allowed
    with pytest.raises(ValueError, match=rf"`dms\[1\].n_modes` must be <= {limit} .* got "
                                         rf"{limit + 1}\."):
        with_values(cfg, "dms", 1, n_modes=limit + 1)
    with pytest.raises(ValueError, match=r"`dms\[0\].n_modes` must be <= 152 \(Zernike "
                                         r"radial order .* = 16 for 32 pixels.*got 800"):
        with_values(cfg, "dms", 0, n_modes=800)  # 32 px across the ground DM: orders <= 16


@pytest.mark.parametrize("n_pixels", [32, 33])
def test_the_dm_sampling_rule_is_the_bases_rule_at_the_same_edge(n_pixels):
    # one copy of the rule (modalinfo.bases.zernike.check_zernike_sampling): on odd and even
    # grids, with the upper DM's disc a non-integer number of pixels across, the largest
    # mode count passes both and one more is refused by both; the edge is Noll's count of
    # modes up to radial order floor(across / 2), written out here
    from modalinfo.bases.zernike import check_zernike_sampling

    cfg = with_values(small(), "wfss", 1, n_subapertures=16)
    cfg = with_values(cfg, "telescope", None, n_pixels=n_pixels)
    fov = cfg.wfss[1].field_of_view
    across = (4.0 + 2 * 10_000 * math.tan(fov / 2 * ARCSEC)) / (4.0 / n_pixels)
    assert across != int(across)
    n_max = int(across // 2)
    limit = (n_max + 1) * (n_max + 2) // 2 - 1
    check_zernike_sampling([limit + 1], int(across))  # Z2 .. Z(limit + 1): accepted
    with_values(cfg, "dms", 1, n_modes=limit)
    with pytest.raises(ValueError, match=rf"`n_pixels` must be >= {2 * (n_max + 1)} "):
        check_zernike_sampling([limit + 2], int(across))
    with pytest.raises(ValueError, match=rf"`dms\[1\].n_modes` must be <= {limit} "):
        with_values(cfg, "dms", 1, n_modes=limit + 1)


def test_subapertures_beyond_the_pupil_sampling_are_refused():
    cfg = small()
    with pytest.raises(ValueError, match=r"`wfss\[0\].n_subapertures` must be <= 16 \(at "
                                         r"least 2 pixels per subaperture.* got 17"):
        with_values(cfg, "wfss", 0, n_subapertures=17)
    with_values(cfg, "wfss", 0, n_subapertures=16)


def test_delay_beyond_the_servo_limit_is_refused_at_load():
    with pytest.raises(ValueError, match=r"`loop.delay` must be <= 1000 frames .* got 0.25"):
        small(time_step=2e-4, integration_time=2e-4, delay=0.25)


@pytest.mark.parametrize(("duration", "match"), [
    (0.0004, r"`duration` must be at least one frame .*got 0.0004 s"),
    (0.0015, r"`duration` must be longer than loop.time_step \+ loop.delay = 0.0025 s"),
])
def test_runs_too_short_for_the_loop_are_refused(duration, match):
    cfg = small(delay=1.5e-3)
    with pytest.raises(ValueError, match=match):
        simulate(cfg, duration, progress=False)


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"budget_every": 16}, r"`budget_every` must be None or an int in \[1, 15\] frames"),
    ({"budget_every": 0}, r"`budget_every` must be None or an int in \[1, 15\]"),
    ({"budget_every": -2}, r"got -2"),
    ({"snapshot_every": 31}, r"`snapshot_every` must be None or an int in \[1, 30\]"),
    ({"snapshot_every": 2.5}, r"got 2.5"),
])
def test_intervals_outside_the_run_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        simulate(small(), 0.03, progress=False, **kwargs)


def test_unstable_gain_is_refused_before_the_setup():
    # half-frame delay, full exposure: W = (z**-1 + z**-2) / 2, stable for gain < 2
    # (test_servo_bounds checks the limits against the polynomial roots)
    with pytest.raises(ValueError, match=r"`loop.gain` = 2.5 makes the loop unstable"):
        simulate(small(gain=2.5), 0.02, progress=False)


# ---------------------------------------------------------------- loop status
def _result(variance):
    cfg = small()
    v = np.asarray(variance, dtype=float)[:, None] * np.ones((1, 9))
    times = (np.arange(v.shape[0]) + 1) * cfg.loop.time_step
    return SimulationResult(config=cfg, seed=0, predictor="none", times=times,
                            directions=np.zeros((9, 2)), residual_variance=v, logs={},
                            elapsed=1.0, version="test")


def test_loop_status_of_hand_made_histories():
    rng = np.random.default_rng(0)
    floor = 0.8 + 0.05 * rng.standard_normal(200)
    drop = np.concatenate([[40.0, 20.0, 9.0, 4.0], floor[4:]])
    r = _result(drop)
    assert r.closed and not r.diverged and r.loop_status == "closed"
    assert r.summary()["closure_time_s"] == pytest.approx(r.closure_time)

    growth = np.concatenate([[40.0, 10.0, 2.0], 1.0 * 1.015 ** np.arange(147)])  # x9
    r = _result(growth)
    assert r.diverged and not r.closed
    assert r.loop_status.startswith("diverged: the residual grew to")

    worse = np.concatenate([[40.0], np.linspace(40.0, 200.0, 99)])
    assert _result(worse).loop_status.startswith("diverged: the residual at the end")

    flat = 40.0 + rng.standard_normal(100)  # never corrected: a delay as long as the run
    r = _result(flat)
    assert not r.closed and not r.diverged
    assert r.loop_status.startswith("did not close")
    s = r.summary()
    assert math.isnan(s["closure_time_s"]) and s["loop_status"] == r.loop_status

    assert _result([40.0, 2.0, 1.0]).loop_status.startswith("did not close: 3 frames")
    # 1-ms frames: closure must hold 5 ms inside the first half, so 10 frames at least
    assert _result(drop[:9]).loop_status.startswith("did not close: 9 frames are too few")
    assert _result(drop[:10]).closed
    nan = drop.copy()
    nan[120:] = np.nan
    assert _result(nan).loop_status == "diverged: the residual is not finite from frame 120"


class Amplified(PersistencePredictor):
    """Forecasts ``factor`` times the last POL (the integrator then over-corrects)."""

    def __init__(self, horizon=2, factor=3.0):
        super().__init__(horizon=horizon)
        self.factor = factor

    def update(self, x_t):
        return self.factor * super().update(x_t)


def test_real_runs_that_diverge_or_never_close_say_so(capsys):
    from closedloop.cli import _summary_line

    cfg = small()
    bad = Amplified().fit(np.zeros((20, 55)))
    run = simulate(cfg, 0.06, predictor=bad, progress=False)
    assert run.diverged, run.loop_status
    line = _summary_line(run)
    assert "loop diverged" in line and "closure at" not in line
    slow = simulate(small(gain=1e-4), 0.04, progress=False)
    assert slow.loop_status.startswith("did not close"), slow.loop_status
    assert "did not close" in _summary_line(slow)


# ---------------------------------------------------------------- resources
def test_estimate_counts_the_arrays_a_config_implies():
    cfg = small()
    long = estimate(cfg, 2.0)
    short = estimate(cfg, 1.0)
    # logs: frames x (3 x 55 modes + 9 directions + measurements) float64, twice; the
    # increment per second is that, whatever the constant parts are
    n_meas = sum(2 * math.pi / 4 * 8 ** 2 for _ in cfg.wfss)
    per_frame = 2 * 8 * (3 * 55 + 9 + n_meas)
    assert long.parts["logs"] - short.parts["logs"] == pytest.approx(1000 * per_frame)
    assert long.drivers["logs"] == "duration"
    # a layer 1000 km up: its plane reaches h x field corner = 1e6 m x 30 sqrt(2)" (the
    # science corner) -> screen 4 n pixels on a side, float64
    d = cfg.to_dict()
    d["layers"][1]["altitude"] = 1e6
    high = SimulationConfig.from_dict(d)
    reach = 2.0 + 1e6 * 30 * math.sqrt(2) * ARCSEC
    n = 2 * math.ceil(reach / (4.0 / 32)) + 6
    est = estimate(high, 0.01)
    assert est.parts["screens"] >= 8.0 * (4 * n) ** 2
    assert est.parts["screens"] <= 8.0 * (4 * n * 1.25) ** 2 + short.parts["screens"]
    assert est.drivers["screens"] == "layers[1].altitude"


@pytest.mark.parametrize(("change", "key"), [
    ({"telescope": {"n_pixels": 6000}}, "telescope.n_pixels"),
    ({"layers": [LayerConfig(altitude=0.0, d_over_r0=20.0, wind_speed=5.0),
                 LayerConfig(altitude=3e7, d_over_r0=2.0, wind_speed=30.0)]},
     "layers[1].altitude"),
    ({"wfss": "field_samples=90"}, "wfss[0].field_samples"),
])
def test_runs_past_the_limit_are_refused_naming_the_key(change, key):
    cfg = small()
    d = cfg.to_dict()
    for k, v in change.items():
        if k == "telescope":
            d[k].update(v)
            d["dms"][0]["n_modes"] = 9
            d["dms"][1]["n_modes"] = 9
        elif k == "layers":
            d[k] = [vars(layer) for layer in v]
        else:
            d["wfss"][0]["field_samples"] = 90
    big = SimulationConfig.from_dict(d)
    with pytest.raises(ResourceError, match=rf"driven by .*`{re_escape(key)}`"):
        check_resources(big, 0.05, limit=2e9)
    with pytest.raises(MemoryError, match="more than 1.86 GiB"):  # 2e9 B (dask's words)
        simulate(big, 0.05, memory_limit=2e9, progress=False)


def test_long_duration_is_refused_by_its_logs():
    with pytest.raises(ResourceError, match=r"largest part, logs .* driven by `duration`"):
        check_resources(small(), 1e6, limit=4e9)
    with pytest.raises(ValueError, match=r"`memory_limit` must be > 0.0; got -1.0"):
        check_resources(small(), 0.1, limit=-1)


def re_escape(text):
    import re

    return re.escape(text)


# ---------------------------------------------------------------- snapshot directions
@pytest.mark.parametrize(("directions", "every", "match"), [
    # the field is [-30", 30"] per axis (small(): 60" wide); 30.5" read past a plane's
    # edge: an IndexError after the whole run before audit 9
    ([[30.5, 0.0]], 2, r"`snapshot_directions` must lie in the science field, \|x\|, \|y\| "
                       r"<= field.size / 2 = 30 arcsec .*got 30.5"),
    ([[0.0, -1e5]], 2, r"field.size / 2 = 30 arcsec .*got 100000"),
    ([[np.nan, 0.0]], 2, r"`snapshot_directions` must be finite"),
    ([1.0, 2.0, 3.0], 2, r"`snapshot_directions` must have shape \(n, 2\) .*got shape \(3,\)"),
    # without snapshot_every the directions were ignored without a word
    ([[0.0, 0.0]], None, r"`snapshot_directions` needs `snapshot_every`"),
])
def test_snapshot_directions_outside_the_field_are_refused(directions, every, match):
    with pytest.raises(ValueError, match=match):
        simulate(small(), 0.003, progress=False, snapshot_every=every,
                 snapshot_directions=np.array(directions))


def test_a_snapshot_at_the_field_corner_is_its_direction_residual():
    # the corner (30", 30") is the last direction of the 3 x 3 grid; the snapshot's
    # plain numpy variance over the pupil is that direction's residual variance
    r = simulate(small(), 0.003, progress=False, snapshot_every=1,
                 snapshot_directions=np.array([[30.0, 30.0]]))
    assert r.snapshots.shape[:2] == (3, 1)
    np.testing.assert_allclose(np.nanvar(r.snapshots[:, 0], axis=(1, 2)),
                               r.residual_variance[:, 8], rtol=1e-10)


def test_progress_of_the_wrong_type_is_refused():
    # "no" is a true string: it drew the bar (audit 9)
    with pytest.raises(TypeError, match=r"`progress` must be None or a bool; got 'no'"):
        simulate(small(), 0.003, progress="no")
