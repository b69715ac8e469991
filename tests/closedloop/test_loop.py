"""The loop as a whole: reproducibility, predictors online, results and telemetry.

References: bit-for-bit identities (same seed twice; persistence against no predictor,
which the control law makes the same arithmetic), the classic integrator written out
here, HDF5 round trips, the oracle bound (a run told the true future cannot do worse
than the same loop without delay, beyond the scatter of the runs), and modalinfo's own
readers on the simulator's logs.
"""

import numpy as np
import pytest

from closedloop import LoopModel, SimulationResult, simulate
from closedloop.config import FieldConfig
from closedloop.control.controller import Controller
from closedloop.control.predictors import ORACLE, LoopPredictor, training_data
from modalinfo.forecast import ARMAPredictor, PersistencePredictor
from modalinfo.ordering import fitting_error
from modalinfo.ordering.fitting_error import PupilSamplingWarning

from .conftest import small


@pytest.fixture(scope="module")
def cfg():
    return small()


@pytest.fixture(scope="module")
def model(cfg):
    return LoopModel(cfg)


@pytest.fixture(scope="module")
def reference(cfg, model):
    return simulate(cfg, 0.15, seed=5, model=model, progress=False)


@pytest.mark.reproducibility
def test_same_seed_same_bits_other_seed_other_bits(cfg, model, reference):
    again = simulate(cfg, 0.15, seed=5, model=model, progress=False)
    np.testing.assert_array_equal(again.residual_variance, reference.residual_variance)
    np.testing.assert_array_equal(again.logs["dm1.commands"].coeffs,
                                  reference.logs["dm1.commands"].coeffs)
    fresh = simulate(cfg, 0.15, seed=5, progress=False)  # a new LoopModel too
    np.testing.assert_array_equal(fresh.residual_variance, reference.residual_variance)
    other = simulate(cfg, 0.15, seed=6, model=model, progress=False)
    assert not np.array_equal(other.residual_variance, reference.residual_variance)


def test_persistence_reproduces_the_no_predictor_run(cfg, model, reference):
    persistence = PersistencePredictor(horizon=3).fit(training_data(reference))
    run = simulate(cfg, 0.15, seed=5, model=model, predictor=persistence, progress=False)
    np.testing.assert_array_equal(run.residual_variance, reference.residual_variance)
    assert run.predictor == "PersistencePredictor"


def test_controller_is_the_classic_integrator_without_predictor():
    rng = np.random.default_rng(0)
    gain, leak = 0.4, 0.01
    ctl = Controller(3, gain=gain, leak=leak, delay_frames=0.5, integration_frames=1.0)
    c = np.zeros(3)
    for _ in range(50):
        m = rng.standard_normal(3)
        c = (1 - leak) * c + gain * m
        got, pol, _ = ctl.step(m)
        np.testing.assert_allclose(got, c, rtol=0, atol=1e-12)
    # POL = measurement + the commands seen during the exposure (w = [0, .5, .5])
    history = []
    ctl = Controller(1, gain=gain, leak=0.0, delay_frames=0.5, integration_frames=1.0)
    for k in range(5):
        m = np.array([float(k)])
        before = list(history)
        cmd, pol, _ = ctl.step(m)
        last = before[-1] if before else 0.0
        second = before[-2] if len(before) > 1 else 0.0
        seen = 0.5 * last + 0.5 * second
        assert pol[0] == pytest.approx(m[0] + seen)
        history.append(cmd[0])


def test_predictor_horizon_must_cover_the_lead():
    with pytest.raises(ValueError, match="horizon"):
        Controller(2, gain=0.5, leak=0.0, delay_frames=1.5, integration_frames=1.0,
                   predictor=PersistencePredictor(horizon=1))


def test_oracle_reaches_the_zero_delay_run(cfg, model, reference):
    # the oracle knows the POL over each command's hold: it must do at least as well as
    # the same loop with no delay at all. Tolerance: the frame-to-frame scatter of the
    # SR peak's mean (its s.e. over ~100 correlated frames is ~0.01).
    oracle = simulate(cfg, 0.15, seed=5, model=model, predictor=ORACLE, progress=False)
    zero = small(delay=0.0)
    zero_run = simulate(zero, 0.15, seed=5, progress=False)
    a = oracle.strehl_peak[oracle.closure_index:].mean()
    b = zero_run.strehl_peak[zero_run.closure_index:].mean()
    c = reference.strehl_peak[reference.closure_index:].mean()
    assert a >= b - 0.02
    assert a > c  # and better than the delayed loop it replaces


def test_trained_predictors_run_online(cfg, model, reference):
    data = training_data(reference)
    assert data.shape[1] == model.n_modes
    assert data.shape[0] <= reference.times.size - 15  # after 15 ms, as in the paper
    arma = LoopPredictor.from_name("arma").trained(reference)
    assert isinstance(arma.predictor, ARMAPredictor)
    run = simulate(cfg, 0.15, seed=5, model=model, predictor=arma, progress=False)
    assert np.all(np.isfinite(run.residual_variance))
    assert run.predictor == "arma"  # the name given, not the class name
    with pytest.raises(ValueError, match="no-prediction"):
        training_data(run)
    with pytest.raises(ValueError, match="predictor"):
        LoopPredictor.from_name("kalman")


def test_result_round_trip_and_no_overwrite(reference, tmp_path):
    path = tmp_path / "run.h5"
    reference.save(path)
    back = SimulationResult.load(path)
    assert back.config == reference.config
    assert back.seed == 5 and back.version == reference.version and back.version
    np.testing.assert_array_equal(back.residual_variance, reference.residual_variance)
    np.testing.assert_array_equal(back.times, reference.times)
    for name, log in reference.logs.items():
        np.testing.assert_array_equal(back.logs[name].coeffs, log.coeffs)
        assert back.logs[name].modes == log.modes
        assert back.logs[name].metadata == log.metadata
        np.testing.assert_array_equal(back.logs[name].times, log.times)
    assert back.corrected_fov_diameter() == reference.corrected_fov_diameter()
    assert len(back.measurements) == len(reference.config.wfss)
    for a, b in zip(back.measurements, reference.measurements, strict=True):
        np.testing.assert_array_equal(a, b)
    with pytest.raises(FileExistsError):
        reference.save(path)
    reference.save(path, overwrite=True)
    (tmp_path / "bad.h5").write_bytes(b"not hdf5")
    with pytest.raises(ValueError, match="bad.h5"):
        SimulationResult.load(tmp_path / "bad.h5")


def test_logs_are_modal_logs_the_library_reads(reference, model):
    log = reference.logs["dm0.pol"]
    assert log.units == "rad" and log.rate == pytest.approx(1000.0)
    assert log.modes == list(range(2, 37))
    assert log.metadata["config"] == reference.config.to_dict()
    from modalinfo.bases import Pupil, ZernikeBasis

    basis = ZernikeBasis(Pupil(32, diameter=4.0), modes=log.modes)
    with pytest.warns(PupilSamplingWarning):  # continuous Zernikes on 32 pixels (fix33-a)
        curve = fitting_error(log, basis)
    assert curve.mean.shape == (log.n_modes,)
    assert curve.mean[-1] < 1e-9 * curve.mean_total  # all modes: nothing left
    assert np.all(np.diff(curve.mean) <= 1e-12 * curve.mean_total)


def test_views(reference):
    n = reference.config.field.n_points
    smap = reference.strehl_map()
    assert smap.shape == (n, n)
    np.testing.assert_allclose(reference.strehl_peak, reference.strehl.max(axis=1))
    assert 0 <= reference.closure_index < reference.times.size // 2
    freqs, psd = reference.strehl_peak_spectrum()
    assert 450.0 < freqs[-1] <= 500.0  # up to the Nyquist frequency of the 1 kHz loop
    d = reference.corrected_fov_diameter(0.3)
    assert 0.0 <= d <= 2 * np.sqrt(2) * reference.config.field.size / 60 / np.sqrt(np.pi) + 1e-9
    with pytest.raises(ValueError, match="threshold"):
        reference.corrected_fov_diameter(1.5)
    # a common window: the mean over the frames from `start`, recomputed here
    np.testing.assert_allclose(reference.strehl_map(start=50).ravel(),
                               reference.strehl[50:].mean(axis=0))
    assert reference.strehl_map(after_closure=False).ravel() == pytest.approx(
        reference.strehl.mean(axis=0))
    with pytest.raises(ValueError, match="start"):
        reference.strehl_map(start=10_000)


def test_corrected_fov_of_a_known_disc():
    # an SR map that is a cone: SR > 0.3 inside a disc of known radius; the refined area
    # must give the disc's diameter back (d = 2 sqrt(A / pi)), to the grid's resolution
    from dataclasses import replace

    c = small()
    n = 41
    c = c.replace(field=FieldConfig(size=120.0, n_points=n))
    v = np.linspace(-60, 60, n)
    yy, xx = np.meshgrid(v, v, indexing="ij")
    radius = 30.0  # arcsec
    sr = np.clip(0.3 + 0.01 * (radius - np.hypot(xx, yy)), 0.01, 0.99)
    variance = np.tile(-np.log(sr).ravel(), (4, 1))
    r = SimulationResult(config=c, seed=0, predictor="none", times=np.arange(1, 5) * 1e-3,
                         directions=np.zeros((n * n, 2)), residual_variance=variance)
    r = replace(r)
    assert r.corrected_fov_diameter(0.3) == pytest.approx(2 * radius / 60, rel=0.01)


def test_three_dms_five_layers_run():
    c = small("mcao3")
    assert len(c.dms) == 3 and len(c.layers) == 5
    run = simulate(c, 0.03, seed=1, progress=False)
    assert set(run.logs) >= {"dm2.commands", "dm2.pol", "dm2.residual"}
    assert np.all(np.isfinite(run.residual_variance))
    # the loop corrects: the last frames are better than the first
    assert run.strehl_peak[-5:].mean() > run.strehl_peak[0]


def test_sensitivity_rows():
    # reference: the wavelength rows rescale the base run's variance by (lambda0/lambda)^2,
    # recomputed here; a variation row equals a direct run of the changed config
    import dataclasses

    from closedloop.studies.sensitivity import markdown, sensitivity

    base = small()

    def fewer_modes(c):
        return c.replace(dms=(dataclasses.replace(c.dms[0], n_modes=20), *c.dms[1:]))

    rows = sensitivity(base, duration=0.05, seed=2, budget_every=None,
                       variations=[("modes", "20", fewer_modes)], progress=False)
    ref = simulate(base, 0.05, seed=2, progress=False)
    start = ref.closure_index
    scale = (base.wavelength / 500e-9) ** 2
    sr500 = np.exp(-ref.residual_variance[start:] * scale).max(axis=1).mean()
    assert rows[1]["strehl_peak"] == pytest.approx(sr500, rel=1e-12)
    direct = simulate(fewer_modes(base), 0.05, seed=2, progress=False)
    assert rows[-1]["strehl_peak"] == pytest.approx(
        direct.strehl_peak[direct.closure_index:].mean(), rel=1e-12)
    assert "| modes | 20 |" in markdown(rows)
