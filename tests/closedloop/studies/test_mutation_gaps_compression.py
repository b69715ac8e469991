"""closedloop.studies.compression: the study's Python, fast, on runs whose numbers are set here.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/studies/compression.py").
``test_compression.py`` runs the kaos loop (minutes per mutant on the shared machine);
this file runs no loop: ``simulate``, ``run_trained``, ``LoopModel``, the RTC timing and
the predictor's training are replaced by recorders, and the orderings are built from a
POL log written here (an AR(1) series, 6 Zernike modes of unequal variance). References,
from outside the code under test:

- the orderings: the identity (Noll order); modalinfo's theoretical K-L,
  ``KLBasis.from_turbulence`` on the log's DM diameter and the smallest outer scale of
  the layers; the eigenvectors of the log's uncentred second-moment matrix by
  ``numpy.linalg.eigh`` (decreasing variance); ``modalinfo.ordering.order_modes``
  ``"mi_greedy"`` for the MI orders; all on the log from the paper's training start
  (``closedloop.control.predictors.training_start``: closure and 15 ms) on, the frames
  before it made different so that using them shows;
- the RTC step: the projected reconstructor ``B^T R`` and POL term ``B^T (R G) B``, the
  controller's lead ``delay + 0.5 + integration / 2`` frames, the median over batches of
  a clock that advances by set amounts;
- the latency law ``delay = readout + compute / rtc_speed`` rounded to
  ``time_step / oversampling``, written out by hand;
- the study's grid by its docstring: which runs are made (with which config, model,
  basis, training reference), which are shared (every mode: one run for all orderings)
  or reused (a modelled delay equal to the fixed one), and the means from the training
  start on, written out by hand run by run.
"""

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from closedloop import presets
from closedloop.control import predictors as cl_predictors
from closedloop.control.predictors import LoopPredictor, training_start
from closedloop.result import SimulationResult
from closedloop.studies import compression as comp
from modalinfo.bases import KLBasis, Pupil, ZernikeBasis
from modalinfo.ordering import order_modes
from modalinfo.telemetry.log import ModalLog

M = 6
T = 120
DM_DIAMETER = 0.9  # the log's metadata; the telescope is 0.7 m: the log's must be used


def _kaos6():
    cfg = presets.get("kaos")
    return cfg.replace(dms=(dataclasses.replace(cfg.dms[0], n_modes=M),),
                       layers=(dataclasses.replace(cfg.layers[0], outer_scale=35.0),
                               dataclasses.replace(cfg.layers[1], outer_scale=12.0)))


def _pol():
    rng = np.random.default_rng(1)
    sd = np.array([3.0, 2.6, 1.0, 0.7, 1.8, 0.4])
    x = np.zeros((T, M))
    for k in range(1, T):
        x[k] = 0.9 * x[k - 1] + rng.standard_normal(M) * sd
    return x


@pytest.fixture(scope="module")
def reference():
    cfg = _kaos6()
    x = _pol()
    times = np.arange(1, T + 1) * cfg.loop.time_step
    # a loop that closed at frame 3 (open-loop level 2 rad^2, then 0.3): the training
    # starts at t > 15 ms, after the closure (a flat 0.3 never rose: it did not close,
    # and would train on its second half)
    v = np.full((T, 1), 0.3)
    v[:3] = 2.0
    ref = SimulationResult(config=cfg, seed=0, predictor="none", times=times,
                           directions=np.zeros((1, 2)), residual_variance=v)
    assert ref.loop_status == "closed" and ref.averaging_start == 3
    start = training_start(ref)
    assert 20 < start < T - 60
    # before the training start, the last mode dominates: an ordering built on those
    # frames would put it first
    x[:start, -1] += 60.0 * np.random.default_rng(2).standard_normal(start)
    log = ModalLog(x, rate=1.0 / cfg.loop.time_step, modes=list(range(2, M + 2)),
                   convention="noll", units="rad", metadata={"dm_diameter_m": DM_DIAMETER},
                   start_time=cfg.loop.time_step)
    return dataclasses.replace(ref, logs={"dm0.pol": log}), start


def _same_columns(a, b, atol=1e-10):
    """Equal up to each column's sign."""
    a, b = np.asarray(a), np.asarray(b)
    assert a.shape == b.shape
    for j in range(a.shape[1]):
        s = 1.0 if a[:, j] @ b[:, j] >= 0 else -1.0
        np.testing.assert_allclose(a[:, j], s * b[:, j], atol=atol, err_msg=f"column {j}")


def test_orderings_against_their_definitions(reference):
    ref, start = reference
    out = comp.control_orderings(ref, seed=3, sample_budget=3000, n_pixels=16)
    assert list(out) == list(comp.ORDERINGS)
    np.testing.assert_array_equal(out["zernike"], np.eye(M))
    log = ref.logs["dm0.pol"][start:]
    zb = ZernikeBasis(Pupil(16, diameter=DM_DIAMETER), modes=list(range(2, M + 2)))
    kl = KLBasis.from_turbulence(Pupil(16, diameter=DM_DIAMETER), M, outer_scale=12.0,
                                 zernike_modes=list(range(2, M + 2)))
    np.testing.assert_allclose(out["kl"], np.asarray(kl.zernike_from_kl), atol=1e-12)
    # data K-L: eigenvectors of the uncentred second moments of the POL from `start` on
    x = np.asarray(log.coeffs)
    w, v = np.linalg.eigh(x.T @ x)
    _same_columns(out["pca"], v[:, np.argsort(w)[::-1]])
    # MI orders: modalinfo's mi_greedy with the seed and budget given, no resampling
    zo = order_modes(log, zb, "mi_greedy", seed=3, sample_budget=3000, n_resamples=0).order
    np.testing.assert_array_equal(out["zernike-mi"], np.eye(M)[:, zo])
    ko = order_modes(log, kl, "mi_greedy", seed=3, sample_budget=3000, n_resamples=0).order
    np.testing.assert_allclose(out["kl-mi"], np.asarray(kl.zernike_from_kl)[:, ko], atol=1e-12)
    assert list(zo) != list(range(M))  # the MI order is not the Noll order here
    # each K-L ordering asked alone builds the theoretical K-L it needs
    for name in ("kl", "kl-mi"):
        alone = comp.control_orderings(ref, orderings=(name,), seed=3, sample_budget=3000,
                                       n_pixels=16)
        assert list(alone) == [name]
        np.testing.assert_allclose(alone[name], out[name], atol=1e-12)


def test_orderings_defaults_and_subset(reference):
    ref, start = reference
    out = comp.control_orderings(ref, orderings=("kl", "zernike-mi"))
    assert list(out) == ["kl", "zernike-mi"]
    log = ref.logs["dm0.pol"][start:]
    # defaults: 48 pixels across, seed 0, 50 000 samples
    kl = KLBasis.from_turbulence(Pupil(48, diameter=DM_DIAMETER), M, outer_scale=12.0,
                                 zernike_modes=list(range(2, M + 2)))
    np.testing.assert_allclose(out["kl"], np.asarray(kl.zernike_from_kl), atol=1e-12)
    zb = ZernikeBasis(Pupil(48, diameter=DM_DIAMETER), modes=list(range(2, M + 2)))
    zo = order_modes(log, zb, "mi_greedy", seed=0, sample_budget=50_000, n_resamples=0).order
    np.testing.assert_array_equal(out["zernike-mi"], np.eye(M)[:, zo])
    only = comp.control_orderings(ref, orderings=("pca",))
    assert list(only) == ["pca"]


def test_orderings_refusals(reference):
    ref, _ = reference
    with pytest.raises(ValueError) as exc:
        comp.control_orderings(ref, orderings=("zernike", "pcb", "foo"))
    assert str(exc.value) == ("`orderings` must be names from zernike, kl, zernike-mi, kl-mi, "
                              "pca; got 'pcb'.")
    msg = "`reference` must be a no-prediction run of a single-DM config."
    with pytest.raises(ValueError) as exc:
        comp.control_orderings(dataclasses.replace(ref, predictor="oracle"))
    assert str(exc.value) == msg
    two = SimpleNamespace(dms=ref.config.dms * 2)
    with pytest.raises(ValueError) as exc:
        comp.control_orderings(SimpleNamespace(predictor="none", config=two))
    assert str(exc.value) == msg


def test_orderings_labels():
    assert comp.ORDERINGS == {
        "zernike": "Zernike, standard order", "kl": "K-L (theory), variance order",
        "zernike-mi": "Zernike, MI order", "kl-mi": "K-L (theory), MI order",
        "pca": "data K-L (PCA of the POL)"}


# ------------------------------------------------------------------ the RTC step
def _loop_config():
    cfg = _kaos6()
    # 1.5 frames of delay, half a frame of exposure: lead 1.5 + 0.5 + 0.25 = 2.25 frames
    return cfg.replace(loop=dataclasses.replace(cfg.loop, delay=0.75e-3,
                                                integration_time=0.25e-3, gain=0.3,
                                                leak=0.01))


def _record_steps(monkeypatch):
    calls = []

    def fake(controller, reconstructor, slopes, repeats, batches):
        calls.append(SimpleNamespace(controller=controller, reconstructor=reconstructor,
                                     slopes=slopes, repeats=repeats, batches=batches))
        return 1.25e-6

    monkeypatch.setattr(comp, "_time_steps", fake)
    return calls


def _basis():
    q, _ = np.linalg.qr(np.random.default_rng(5).standard_normal((M, M)))
    return q


def test_rtc_compute_time_times_the_projected_step(monkeypatch):
    calls = _record_steps(monkeypatch)
    rng = np.random.default_rng(6)
    r = rng.standard_normal((M, 10))
    s = rng.standard_normal((M, M))
    model = SimpleNamespace(reconstructor=r, wfss=[SimpleNamespace(reconstructor=None)],
                            config=_loop_config(), sensed_commands=s)
    b = _basis()[:, :2]
    pred = SimpleNamespace(horizon=3, reset=lambda: None)
    assert comp.rtc_compute_time(model, b, pred, repeats=7, batches=3, seed=4) == 1.25e-6
    c = calls[-1]
    np.testing.assert_allclose(c.reconstructor, b.T @ r, rtol=1e-13, atol=1e-15)
    assert c.reconstructor.flags.c_contiguous and c.reconstructor.dtype == np.float64
    assert (c.repeats, c.batches) == (7, 3)
    assert c.slopes.shape == (64, 10)
    assert 0.5e-7 < c.slopes.std() < 2e-7  # measurement-sized slopes [rad/m], 1e-7 rms
    ctl = c.controller
    assert (ctl.n_modes, ctl.gain, ctl.leak, ctl.predictor) == (2, 0.3, 0.01, pred)
    assert ctl.lead == pytest.approx(2.25, abs=1e-12)
    np.testing.assert_allclose(ctl.sensed, b.T @ s @ b, rtol=1e-13, atol=1e-15)
    # the seed sets the slopes; the defaults: 2000 steps, 5 batches, seed 0
    comp.rtc_compute_time(model, b, pred, repeats=7, batches=3, seed=4)
    np.testing.assert_array_equal(calls[-1].slopes, c.slopes)
    comp.rtc_compute_time(model, b)
    assert (calls[-1].repeats, calls[-1].batches) == (2000, 5)
    assert calls[-1].controller.predictor is None
    assert not np.array_equal(calls[-1].slopes, c.slopes)
    comp.rtc_compute_time(model, b, seed=0)
    np.testing.assert_array_equal(calls[-1].slopes, calls[-2].slopes)


def test_rtc_compute_time_without_a_global_reconstructor(monkeypatch):
    calls = _record_steps(monkeypatch)
    r = np.random.default_rng(7).standard_normal((M, 12))
    model = SimpleNamespace(reconstructor=None, wfss=[SimpleNamespace(reconstructor=r)],
                            config=_kaos6(), sensed_commands=None)
    b = _basis()[:, :3]
    comp.rtc_compute_time(model, b.tolist())  # a nested list is a basis too
    c = calls[-1]
    np.testing.assert_allclose(c.reconstructor, b.T @ r, rtol=1e-13, atol=1e-15)
    assert c.controller.sensed is None and c.controller.n_modes == 3
    assert c.controller.lead == pytest.approx(2.0, abs=1e-12)  # kaos: 1 + 0.5 + 0.5


class _Controller:
    def __init__(self):
        self.inputs = []

    def step(self, x):
        self.inputs.append(np.array(x))


def test_time_steps_is_the_median_batch_mean(monkeypatch):
    # a clock advancing 3, 1 and 6 s over the three batches of 4 steps
    readings = iter([0.0, 3.0, 10.0, 11.0, 20.0, 26.0])
    monkeypatch.setattr(comp, "time", SimpleNamespace(perf_counter=lambda: next(readings)))
    ctl = _Controller()
    recon = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    slopes = np.array([[k, 10.0 * k] for k in range(5)])
    assert comp._time_steps(ctl, recon, slopes, 4, 3) == 0.75  # median(3, 1, 6) / 4
    # 50 warm-up steps, then 3 x 4 timed ones; step k reads slopes[k % 5]
    order = [k % 5 for k in range(50)] + [0, 1, 2, 3] * 3
    assert len(ctl.inputs) == len(order)
    for x, k in zip(ctl.inputs, order, strict=True):
        np.testing.assert_array_equal(x, [k, 10.0 * k, 11.0 * k])


def test_rtc_scaling_sizes_and_controller(monkeypatch):
    calls = _record_steps(monkeypatch)
    out = comp.rtc_scaling([3, 1, 50], measurements_per_mode=2.5, gain=0.4, repeats=9)
    np.testing.assert_array_equal(out, [1.25e-6] * 3)
    assert isinstance(out, np.ndarray)
    # 2.5 x 3 = 7.5 -> 8 (rounded half to even), 2.5 x 1 -> 2, 2.5 x 50 = 125
    assert [c.reconstructor.shape for c in calls] == [(3, 8), (1, 2), (50, 125)]
    assert [c.slopes.shape for c in calls] == [(64, 8), (64, 2), (64, 125)]
    for c, n in zip(calls, (3, 1, 50), strict=True):
        assert (c.repeats, c.batches) == (9, 3)
        ctl = c.controller
        assert (ctl.n_modes, ctl.gain, ctl.leak, ctl.predictor) == (n, 0.4, 0.0, None)
        assert ctl.lead == pytest.approx(2.0, abs=1e-12)  # one frame of delay and exposure
    # a random reconstructor whose rows have unit norm on average (entries 1/sqrt(n_meas))
    r = calls[-1].reconstructor
    assert np.mean(np.sum(r ** 2, axis=1)) == pytest.approx(1.0, rel=0.1)
    assert np.std(calls[-1].slopes) == pytest.approx(1.0, rel=0.1)
    calls.clear()
    comp.rtc_scaling([2], measurements_per_mode=0.1)  # at least one measurement
    assert calls[0].reconstructor.shape == (2, 1)
    assert (calls[0].repeats, calls[0].controller.gain) == (500, 0.5)  # documented defaults
    calls.clear()
    comp.rtc_scaling([4], seed=1)
    first = calls[0].reconstructor
    assert first.shape == (4, 8)  # the documented default: 2 measurements per mode
    comp.rtc_scaling([4], seed=1)
    comp.rtc_scaling([4], seed=2)
    np.testing.assert_array_equal(calls[1].reconstructor, first)
    assert not np.array_equal(calls[2].reconstructor, first)
    np.testing.assert_array_equal(comp.rtc_scaling([4]), [1.25e-6])  # default seed 0
    comp.rtc_scaling([4], seed=0)
    np.testing.assert_array_equal(calls[3].reconstructor, calls[4].reconstructor)
    np.testing.assert_array_equal(calls[3].slopes, calls[4].slopes)


def test_rtc_scaling_fits_the_named_predictor(monkeypatch):
    calls = _record_steps(monkeypatch)
    comp.rtc_scaling([3], predictor="linear-ls", repeats=2)
    pred = calls[0].controller.predictor
    assert type(pred).__name__ == "LinearPredictor"
    # fitted on an AR(1) series of coefficient 0.95: the LS two-tap predictor
    # x_{k+1} = a x_k + b x_{k-1} has a + b near 0.95 (an AR(1) is its own one-tap model)
    # (a, b) near (0.95, 0): the one-step AR(1) (200 samples; each weight's standard
    # error ~0.07 with regressors correlated at 0.95, so 0.35 is 5 of them)
    coef = pred.coef_
    assert coef.shape == (3, 2)
    assert np.all(np.abs(coef.sum(axis=1) - 0.95) < 0.1)
    assert np.all(np.abs(coef[:, 0] - 0.95) < 0.35) and np.all(np.abs(coef[:, 1]) < 0.35)


def test_rtc_scaling_trains_on_enough_samples(monkeypatch):
    # the VAR's minimum at 10 modes is 404 samples (its _min_samples_rule), more than the
    # 200-sample floor: the series must follow the predictor's rule (x 1.2) to be fitted
    calls = _record_steps(monkeypatch)
    pred = cl_predictors.LoopPredictor.from_name("multivariate").predictor
    assert pred._min_samples_rule(10)[0] > 240
    comp.rtc_scaling([10], predictor="multivariate", repeats=2)
    assert calls[0].controller.predictor is not None


# ------------------------------------------------------------------ latency, study views
def test_latency_law_by_hand():
    lat = comp.LatencyModel(readout=0.3e-3, rtc_speed=2.0, oversampling=16)
    # 0.3 + 0.7 / 2 = 0.65 ms on a 1 / 16 ms grid: 10.4 steps -> 10 -> 0.625 ms
    assert lat.delay(0.7e-3, 1e-3) == pytest.approx(0.625e-3, abs=1e-15)
    # 0.3 + 0.9 / 2 = 0.75 ms: 12 steps exactly
    assert lat.delay(0.9e-3, 1e-3) == pytest.approx(0.75e-3, abs=1e-15)
    d = comp.LatencyModel(readout=0.5e-3)
    assert (d.rtc_speed, d.oversampling) == (1.0, 8)
    # 0.5 + 0.1 = 0.6 ms on a 0.0625 ms grid: 9.6 -> 10 -> 0.625 ms
    assert d.delay(0.1e-3, 0.5e-3) == pytest.approx(0.625e-3, abs=1e-15)


def _study(peak, field=None):
    n_values = np.array([2, 4, 8, 16])
    return comp.CompressionStudy(
        config_name="x", seed=0, duration=0.1, n_values=n_values, orderings=("kl",),
        predictor="arma", strehl_peak=peak, strehl_field=field or peak, compute_time={},
        delay={}, latency=comp.LatencyModel(readout=0.5e-3), time_step=0.5e-3,
        window_start=0.015, wavelength=630e-9)


def test_optimum_and_modes_to_reach():
    peak = {(True, "kl", "arma"): np.array([0.1, np.nan, 0.5, 0.4]),
            (False, "kl", "arma"): np.array([0.6, 0.2, 0.1, 0.0]),
            (False, "kl", "none"): np.array([0.25, 0.375, 0.4375, 0.5]),
            (True, "kl", "none"): np.array([0.05, 0.1, 0.2, 0.4])}
    field = {k: v[::-1].copy() for k, v in peak.items()}
    s = _study(peak, field)
    assert s.optimum("kl", "arma") == (8, 0.5)  # latency by default; NaN skipped
    assert s.optimum("kl", "arma", latency=False) == (2, 0.6)
    assert s.optimum("kl", "arma", field_average=True) == (4, 0.5)
    assert s.optimum("kl", "none", field_average=True) == (2, 0.4)
    assert type(s.optimum("kl", "none")[0]) is int
    # fewest modes reaching a fraction of the all-mode SR peak (fixed delay, no prediction
    # by default): 0.75 x 0.5 = 0.375 (binary fractions, exact) is reached at 4 modes,
    # exactly; 0.8 x 0.5 = 0.4 at 8
    assert s.modes_to_reach(0.75, "kl") == 4
    assert s.modes_to_reach(0.8, "kl") == 8
    assert s.modes_to_reach(0.5, "kl", latency=True) == 8
    assert s.modes_to_reach(1.0, "kl", "arma") == 2  # the first n is above the last
    assert s.modes_to_reach(1.1, "kl", latency=True) is None
    assert type(s.modes_to_reach(0.8, "kl")) is int
    assert s.timings == {}


# ------------------------------------------------------------------ the runs, recorded
class _Run:
    """A finished run: SR peak ``v`` and field SR ``0.75 v`` from frame ``start`` on."""

    def __init__(self, v, start, n_frames=40):
        self.strehl_peak = np.r_[np.full(start, 9.0), np.full(n_frames - start, v)]
        self.strehl = np.column_stack([self.strehl_peak / 2, self.strehl_peak])
        self.closure_index = self.averaging_start = 3   # a loop that closed at frame 3
        self.diverged = False
        self.times = np.arange(1, n_frames + 1) * 0.5e-3
        self.v = v


def _start():
    return training_start(_Run(0.0, 0))


@pytest.fixture
def recorder(monkeypatch):
    rec = SimpleNamespace(runs=[], models=[], sims=[], trained=[], rtc=[])

    class FakeModel:
        def __init__(self, config):
            self.config = config
            self.n_modes = 4  # the study's runs control 2 or all 4 modes
            self.dms = [SimpleNamespace(shapes=object())]
            rec.models.append(self)

    def simulate(config, duration, *, model, seed, progress):
        rec.sims.append(dict(config=config, duration=duration, model=model, seed=seed,
                             progress=progress))
        return _Run(0.5, _start())

    def run_trained(config, name, duration, *, seed, model, progress, reference=None,
                    control_basis=None):
        run = _Run(0.01 * (len(rec.runs) + 1), _start())
        rec.runs.append(dict(config=config, name=name, duration=duration, seed=seed,
                             model=model, progress=progress, reference=reference,
                             basis=control_basis, run=run))
        return run

    def trained(self, reference, basis=None):
        rec.trained.append((self.name, reference, basis))
        return SimpleNamespace(predictor=("fitted", basis.shape[1]))

    def rtc(model, basis, predictor=None):
        rec.rtc.append((model, basis, predictor))
        n = basis.shape[1]  # 10 and 40 us without prediction, 100 and 200 us with it
        return 2.5e-6 * n * n if predictor is None else 50e-6 * n

    monkeypatch.setattr(comp, "LoopModel", FakeModel)
    monkeypatch.setattr(comp, "simulate", simulate)
    monkeypatch.setattr(comp, "run_trained", run_trained)
    monkeypatch.setattr(comp, "rtc_compute_time", rtc)
    monkeypatch.setattr(LoopPredictor, "trained", trained)
    rec.FakeModel = FakeModel
    return rec


BZ = np.eye(4)
BP = np.eye(4)[:, [3, 1, 0, 2]]


def test_predictor_screen(recorder):
    cfg = _kaos6()
    out = comp.predictor_screen(cfg, ("linear", "oracle", "arma", "linear"), duration=0.02,
                                seed=5)
    # the model and the reference run made when not given
    assert [m.config for m in recorder.models] == [cfg]
    assert recorder.sims == [dict(config=cfg, duration=0.02, model=recorder.models[0], seed=5,
                                  progress=False)]
    assert [r["name"] for r in recorder.runs] == ["oracle", "linear", "arma"]
    for r in recorder.runs:
        assert (r["config"], r["duration"], r["seed"], r["model"], r["progress"]) == (
            cfg, 0.02, 5, recorder.models[0], False)
        assert r["reference"].v == 0.5
    assert list(out) == ["none", "oracle", "linear", "arma"]
    assert out == pytest.approx({"none": 0.5, "oracle": 0.01, "linear": 0.02, "arma": 0.03},
                                rel=1e-12)
    # given a model and a reference, neither is made
    ref, model = _Run(0.25, _start()), object()
    out = comp.predictor_screen(cfg, (), duration=0.02, model=model, reference=ref)
    assert len(recorder.models) == 1 and len(recorder.sims) == 1
    assert recorder.runs[-1]["model"] is model and recorder.runs[-1]["reference"] is ref
    assert recorder.runs[-1]["seed"] == 0
    assert out == pytest.approx({"none": 0.25, "oracle": 0.04}, rel=1e-12)
    # audit 10, feedback: a reference of another seed, config or predictor is refused
    other_cfg = cfg.replace(loop=dataclasses.replace(cfg.loop, gain=0.2))
    for key, value in (("seed", 1), ("predictor", "arma"), ("config", other_cfg)):
        other = _Run(0.25, _start())
        setattr(other, key, value)
        with pytest.raises(ValueError, match=f"its `{key}` differs"):
            comp.predictor_screen(cfg, (), duration=0.02, model=model, reference=other)


def test_study_grid_by_hand(recorder, monkeypatch):
    cfg = _kaos6()  # fixed delay 0.5 ms, frames of 0.5 ms
    monkeypatch.setattr(comp, "control_orderings",
                        lambda ref, *, orderings, seed: (
                            recorder.orderings.append((ref, orderings, seed))
                            or {"zernike": BZ, "pca": BP}))
    recorder.orderings = []
    said = []
    study = comp.compression_study(cfg, n_values=[4, 2, 2], duration=0.02,
                                   orderings=["zernike", "pca"], predictor="linear-ls",
                                   seed=7, progress=said.append)
    model = recorder.models[0]
    assert model.config == cfg
    ref = recorder.sims[0]
    assert ref == dict(config=cfg, duration=0.02, model=model, seed=7, progress=False)
    reference = recorder.orderings[0][0]
    assert recorder.orderings == [(reference, ("zernike", "pca"), 7)]
    start = _start()
    # RTC times of the first ordering's first n columns, without and with the predictor
    # trained on the reference projected on them
    assert [(m is model, b.tolist(), p) for m, b, p in recorder.rtc] == [
        (True, BZ[:, :2].tolist(), None), (True, BZ[:, :2].tolist(), ("fitted", 2)),
        (True, BZ[:, :4].tolist(), None), (True, BZ[:, :4].tolist(), ("fitted", 4))]
    assert [(name, r is reference, b.tolist()) for name, r, b in recorder.trained] == [
        ("linear-ls", True, BZ[:, :2].tolist()), ("linear-ls", True, BZ[:, :4].tolist())]
    np.testing.assert_array_equal(study.compute_time["none"], [10e-6, 40e-6])
    np.testing.assert_array_equal(study.compute_time["linear-ls"], [100e-6, 200e-6])
    # delays: 0.5 ms + compute on the 0.0625 ms grid: 0.51 -> 0.5; 0.54 -> 0.5625;
    # 0.6 -> 0.625; 0.7 -> 0.6875
    np.testing.assert_allclose(study.delay["none"], [0.5e-3, 0.5625e-3], atol=1e-15)
    np.testing.assert_allclose(study.delay["linear-ls"], [0.625e-3, 0.6875e-3], atol=1e-15)
    assert set(study.delay) == set(study.compute_time) == {"none", "linear-ls"}
    # the runs, in order: fixed delay (zernike 2, pca 2, zernike 4; pca 4 shares
    # zernike's), then the latency runs not equal to a fixed one
    runs = recorder.runs
    want = [  # (ordering basis, n, predictor, delay, reference run index)
        (BZ, 2, "none", 0.5e-3, None), (BZ, 2, "linear-ls", 0.5e-3, 0),
        (BP, 2, "none", 0.5e-3, None), (BP, 2, "linear-ls", 0.5e-3, 2),
        (BZ, 4, "none", 0.5e-3, None), (BZ, 4, "linear-ls", 0.5e-3, 4),
        (BZ, 2, "linear-ls", 0.625e-3, 0), (BP, 2, "linear-ls", 0.625e-3, 2),
        (BZ, 4, "none", 0.5625e-3, 4), (BZ, 4, "linear-ls", 0.6875e-3, 4)]
    assert len(runs) == len(want)
    for k, (r, (b, n, name, delay, ref_k)) in enumerate(zip(runs, want, strict=True)):
        np.testing.assert_array_equal(r["basis"], b[:, :n], err_msg=str(k))
        if name == "none":
            assert r["name"] == "none", k
        else:
            assert isinstance(r["name"], LoopPredictor) and r["name"].name == name, k
        assert r["config"].loop.delay == pytest.approx(delay, abs=1e-15), k
        assert r["config"] == cfg.replace(loop=dataclasses.replace(cfg.loop,
                                                                   delay=r["config"].loop.delay))
        assert r["model"].config is r["config"], k
        assert (r["duration"], r["seed"], r["progress"]) == (0.02, 7, False), k
        if ref_k is None:
            assert r["reference"] is None, k
        else:
            assert r["reference"] is runs[ref_k]["run"], k
    # fixed-delay runs on the given model; one new model per new delay, built once
    assert all(r["model"] is model for r in runs[:6])
    assert [m.config.loop.delay for m in recorder.models[1:]] == pytest.approx(
        [0.625e-3, 0.5625e-3, 0.6875e-3], abs=1e-15)
    assert runs[6]["model"] is runs[7]["model"]
    v = [r["run"].v for r in runs]
    grid = {(False, "zernike", "none"): [v[0], v[4]], (False, "zernike", "linear-ls"): [v[1], v[5]],
            (False, "pca", "none"): [v[2], v[4]], (False, "pca", "linear-ls"): [v[3], v[5]],
            (True, "zernike", "none"): [v[0], v[8]], (True, "zernike", "linear-ls"): [v[6], v[9]],
            (True, "pca", "none"): [v[2], v[8]], (True, "pca", "linear-ls"): [v[7], v[9]]}
    assert set(study.strehl_peak) == set(grid) == set(study.strehl_field)
    for key, peak in grid.items():
        np.testing.assert_allclose(study.strehl_peak[key], peak, rtol=1e-12, err_msg=str(key))
        np.testing.assert_allclose(study.strehl_field[key], 0.75 * np.array(peak), rtol=1e-12,
                                   err_msg=str(key))
    assert said == ["reference run (every mode, no prediction)",
                    "zernike n=2: none", "zernike n=2: linear-ls", "pca n=2: none",
                    "pca n=2: linear-ls", "zernike n=4: none", "zernike n=4: linear-ls",
                    "latency zernike n=2: linear-ls", "latency pca n=2: linear-ls",
                    "latency zernike n=4: none", "latency zernike n=4: linear-ls"]
    # the study's record
    assert (study.config_name, study.seed, study.duration, study.orderings, study.predictor,
            study.time_step, study.wavelength) == ("kaos", 7, 0.02, ("zernike", "pca"),
                                                   "linear-ls", 0.5e-3, 630e-9)
    np.testing.assert_array_equal(study.n_values, [2, 4])
    assert study.n_values.dtype == np.int64
    assert study.window_start == _Run(0.0, 0).times[start]
    assert study.latency == comp.LatencyModel(readout=0.5e-3)
    assert set(study.timings) == {"orderings", "compute_time", "runs"}
    assert all(0.0 <= t < 60.0 for t in study.timings.values())


def test_study_given_model_reference_and_latency(recorder, monkeypatch):
    cfg = _kaos6()
    seen = []
    monkeypatch.setattr(comp, "control_orderings",
                        lambda ref, *, orderings, seed: seen.append(ref) or {"kl": BP})
    model = recorder.FakeModel(cfg)
    ref = _Run(0.5, _start())
    lat = comp.LatencyModel(readout=0.5e-3, rtc_speed=1e6)  # compute costs nothing
    study = comp.compression_study(cfg, n_values=[4], duration=0.02, orderings=("kl",),
                                   predictor="persistence", model=model, reference=ref,
                                   latency=lat)
    assert recorder.sims == [] and len(recorder.models) == 1 and seen == [ref]
    assert study.latency is lat and study.seed == 0
    # every latency run has the fixed delay: the fixed runs are reused, none is made again
    assert len(recorder.runs) == 2
    assert recorder.runs[1]["reference"] is recorder.runs[0]["run"]
    for name in ("none", "persistence"):
        np.testing.assert_array_equal(study.strehl_peak[(True, "kl", name)],
                                      study.strehl_peak[(False, "kl", name)])


def test_study_refusals(recorder):
    cfg = _kaos6()
    model = recorder.FakeModel(cfg)
    for bad, shown in (([0, 4], "[0, 4]"), ([5], "[5]"), ([], "[]"), ([4, 5], "[4, 5]")):
        with pytest.raises(ValueError) as exc:
            comp.compression_study(cfg, n_values=bad, duration=0.02, model=model)
        assert str(exc.value) == f"`n_values` must lie in 1..4; got {shown}."
    for name in ("none", "oracle", "nope"):
        with pytest.raises(ValueError) as exc:
            comp.compression_study(cfg, n_values=[2], duration=0.02, model=model,
                                   predictor=name)
        assert str(exc.value) == (
            "`predictor` must be a predictor name of closedloop.control.predictors.NAMES "
            f"other than 'none' and 'oracle'; got {name!r}.")
    assert "multivariate" in cl_predictors.NAMES  # the documented default is a name
    two = SimpleNamespace(n_modes=M, dms=[SimpleNamespace(shapes=object())] * 2)
    zonal = SimpleNamespace(n_modes=M, dms=[SimpleNamespace(shapes=None)])
    for m, k in ((two, 2), (zonal, 1)):
        with pytest.raises(ValueError) as exc:
            comp.compression_study(cfg, n_values=[2], duration=0.02, model=m)
        assert str(exc.value) == ("the compression study needs a single modal (Zernike) DM; "
                                  f"the config has {k} DMs.")


def test_study_default_predictor_one_mode_and_three_shared_orderings(recorder, monkeypatch):
    cfg = _kaos6()
    bases = {"zernike": BZ, "pca": BP, "kl": BP[:, ::-1]}
    monkeypatch.setattr(comp, "control_orderings",
                        lambda ref, *, orderings, seed: {o: bases[o] for o in orderings})
    model = recorder.FakeModel(cfg)
    study = comp.compression_study(cfg, n_values=[4, 1], duration=0.02,
                                   orderings=("zernike", "pca", "kl"), model=model,
                                   reference=_Run(0.5, _start()),
                                   latency=comp.LatencyModel(readout=0.5e-3, rtc_speed=1e6))
    # the documented default predictor; n = 1 is allowed (n_values lie in 1..n_modes)
    assert study.predictor == "multivariate"
    assert [name for name, _, _ in recorder.trained] == ["multivariate"] * 2
    np.testing.assert_array_equal(study.n_values, [1, 4])
    # every mode (n = 4): one run per predictor, shared by all three orderings
    assert [(r["basis"].shape[1], r["name"] if r["name"] == "none" else r["name"].name)
            for r in recorder.runs] == [(1, "none"), (1, "multivariate"), (1, "none"),
                                        (1, "multivariate"), (1, "none"), (1, "multivariate"),
                                        (4, "none"), (4, "multivariate")]
    for key, peak in study.strehl_peak.items():
        assert np.all(np.isfinite(peak)), key
        assert peak[1] == study.strehl_peak[(key[0], "zernike", key[2])][1], key


@pytest.mark.parametrize(("kwargs", "exc", "match"), [
    # 0 modes was timed as a size, 2.7 as 2, repeats 0 a ZeroDivisionError (audit 9)
    ({"n_values": [0]}, ValueError, r"`n_values\[\*\]` must be an int >= 1; got 0"),
    ({"n_values": [2.7]}, TypeError, r"`n_values\[\*\]` must be an int; got 2.7"),
    ({"n_values": []}, ValueError, r"`n_values` must hold at least one number of modes"),
    ({"n_values": [4], "repeats": 0}, ValueError, r"`repeats` must be an int >= 1; got 0"),
    ({"n_values": [4], "measurements_per_mode": -1.0}, ValueError,
     r"`measurements_per_mode` must be > 0"),
])
def test_rtc_scaling_refuses_sizes_that_are_not_counts(monkeypatch, kwargs, exc, match):
    calls = _record_steps(monkeypatch)
    with pytest.raises(exc, match=match):
        comp.rtc_scaling(**kwargs)
    assert not calls  # refused before any timing
