"""The joint MAP reconstructor (``loop.reconstructor = "map"``) and its controlled projector.

References, from outside the code under test:

- the MAP's closed form ``(G^T N^-1 G + C^-1)^-1 G^T N^-1`` (Fusco et al. 2001, JOSA A
  18, 2527), solved here with ``numpy.linalg.solve`` on the normal equations, on a small
  random ``G``, ``N``, ``C`` and on the model's ``G`` with ``N`` and ``C`` written from
  the config and the documentation (``test_mutation_gaps_model``'s helpers);
- its limits: a prior much larger than the noise gives the Gauss-Markov (weighted least
  squares) estimator ``(G^T N^-1 G)^-1 G^T N^-1``; a tiny prior gives the first order
  ``C G^T N^-1`` (the estimate goes to 0 with the prior);
- linear algebra: a projector is idempotent, its rank is its trace; the MAP's ``R G`` has
  the eigenvalues ``s^2 / (s^2 + 1)`` of the whitened singular values (``numpy.linalg.svd``
  of ``N^-1/2 G C^1/2``), so exactly the directions with ``s > 1`` have eigenvalues above
  one half: the subspace the truncated reconstructor keeps (its ``R G``, by the same
  config with ``"truncated"``);
- pseudo-open-loop control (Ellerbroek & Vogel 2003; Gilles 2005): on a static
  turbulence ``phi`` seen through ``R G`` the commands converge to the MAP estimate
  ``R G phi`` of the open-loop measurements (the plain integrator to ``phi`` itself, at
  the gain ``g R G``); the law written out in the test, frame by frame;
- a persistence forecast changes nothing (its change over the POL is 0, so the projector
  and the pseudo-open-loop POL leave the loop's bits as without a predictor), and a
  rotated control basis of every mode is the same loop (an orthogonal change of
  coordinates);
- the error budget adds up to the measured residual (the terms are estimated
  independently, ``closedloop.budget``) with the MAP as with the truncated form.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from closedloop import simulate
from closedloop.config import LoopConfig, config_text
from closedloop.control.controller import Controller
from closedloop.control.predictors import training_data
from closedloop.model import LoopModel, map_reconstructor
from modalinfo.forecast import PersistencePredictor

from .test_loop import small
from .test_mutation_gaps_model import _config, _interaction, _noise, _prior


def _closed_form(g, noise, prior):
    gn = g.T / noise[None, :]
    return np.linalg.solve(gn @ g + np.diag(1.0 / prior), gn)


@pytest.fixture(scope="module")
def random_problem():
    rng = np.random.default_rng(29)
    g = rng.standard_normal((20, 8))
    noise = rng.uniform(0.5, 2.0, 20)
    prior = rng.uniform(0.1, 3.0, 8)
    return g, noise, prior


def test_map_is_the_closed_form_on_a_random_problem(random_problem):
    g, noise, prior = random_problem
    r = map_reconstructor(g, noise, prior)
    expected = _closed_form(g, noise, prior)
    np.testing.assert_allclose(r, expected, rtol=1e-10, atol=1e-12 * np.abs(expected).max())


def test_map_limits_are_least_squares_and_zero(random_problem):
    g, noise, prior = random_problem
    gn = g.T / noise[None, :]
    gauss_markov = np.linalg.solve(gn @ g, gn)
    wide = map_reconstructor(g, noise, prior * 1e8)
    np.testing.assert_allclose(wide, gauss_markov, rtol=1e-6,
                               atol=1e-7 * np.abs(gauss_markov).max())
    tiny = map_reconstructor(g, noise, prior * 1e-12)
    first_order = 1e-12 * prior[:, None] * gn  # the next order is ~1e-10 of it
    np.testing.assert_allclose(tiny, first_order, rtol=1e-6,
                               atol=1e-7 * np.abs(first_order).max())
    assert np.abs(tiny).max() < 1e-10 * np.abs(gauss_markov).max()


@pytest.mark.parametrize("bad, word", [
    (dict(noise=np.ones(19)), "`noise`"), (dict(prior=np.r_[np.ones(7), 0.0]), "`prior`"),
    (dict(noise=np.r_[np.ones(19), np.nan]), "`noise`"), (dict(interaction=np.ones(3)),
                                                          "`interaction`")])
def test_map_refuses_bad_input_by_name(random_problem, bad, word):
    g, noise, prior = random_problem
    kw = dict(interaction=g, noise=noise, prior=prior) | bad
    with pytest.raises(ValueError, match=word):
        map_reconstructor(**kw)


def _with(cfg, reconstructor):
    return cfg.replace(loop=dataclasses.replace(cfg.loop, reconstructor=reconstructor))


@pytest.fixture(scope="module")
def cut_case():
    # table1's model error on two nearly degenerate mirrors (both 6 m, 20" fields): the
    # truncated form drops directions, so MAP and truncated differ and both are tested
    cfg = _config(noises=(0.002, 0.006), fields=(20.0, 20.0), diameters=(6.0, 6.0),
                  model_error=0.3)
    return cfg, LoopModel(_with(cfg, "map")), LoopModel(cfg)


def test_model_map_is_the_closed_form_with_n_and_c_from_the_config(cut_case):
    cfg, model, truncated = cut_case
    g = _interaction(model)
    prior = _prior(cfg, model)
    noise = _noise(cfg, model, g, prior)
    expected = _closed_form(g, noise, prior)
    np.testing.assert_allclose(model.reconstructor, expected, rtol=1e-7,
                               atol=1e-9 * np.abs(expected).max())
    # the truncated form cuts here, so it is another estimator
    assert truncated.n_controlled < truncated.n_modes
    assert np.abs(truncated.reconstructor - expected).max() > 1e-2 * np.abs(expected).max()


def test_the_map_set_up_leaves_the_spectrum_until_asked(cut_case):
    # the eigen-decomposition of W^T W serves only n_controlled and the projector (~27 s
    # at est-mcao's size): a model that is only run, without a predictor, never pays it
    cfg, _, truncated = cut_case
    model = LoopModel(_with(cfg, "map"))
    assert "_spectrum" not in vars(model)
    assert model.n_controlled == truncated.n_controlled
    assert "_spectrum" in vars(model)


def test_map_projector_is_the_directions_seen_above_the_noise(cut_case):
    cfg, model, truncated = cut_case
    p = model.controlled_projector
    np.testing.assert_allclose(p @ p, p, atol=1e-9)
    rg = model.reconstructor @ _interaction(model)
    # R G itself is no projector with the MAP: it shrinks the weakly seen directions
    assert np.abs(rg @ rg - rg).max() > 1e-2
    # its eigenvalues are s^2 / (s^2 + 1) of the whitened singular values
    prior = _prior(cfg, model)
    noise = _noise(cfg, model, _interaction(model), prior)
    white = _interaction(model) * np.sqrt(prior)[None, :] / np.sqrt(noise)[:, None]
    sv = np.linalg.svd(white, compute_uv=False)
    eig = np.sort(np.linalg.eigvals(rg).real)[::-1]
    np.testing.assert_allclose(eig, sv ** 2 / (sv ** 2 + 1.0), atol=1e-9)
    seen = int(np.sum(sv > 1.0))
    assert 0 < seen < model.n_modes
    assert model.n_controlled == truncated.n_controlled == seen
    assert np.trace(p) == pytest.approx(seen, abs=1e-8)
    # the same subspace as the truncated reconstructor's projector R G, and R G's own
    # invariant subspace (P commutes with it)
    np.testing.assert_allclose(p, truncated.controlled_projector, atol=1e-7)
    np.testing.assert_allclose(p @ rg, rg @ p, atol=1e-9)


def test_reconstructor_option_is_validated_and_truncated_is_left_out_of_files():
    with pytest.raises(ValueError, match=r"`loop.reconstructor` must be one of 'truncated', "
                                         r"'map'; got 'MAP'"):
        _with(small(), "MAP")
    assert LoopConfig().reconstructor == "truncated"
    assert "reconstructor" not in config_text(small())
    assert 'reconstructor = "map"' in config_text(_with(small(), "map"))


def test_error_budget_adds_up_with_the_map():
    # as test_physics.test_error_budget_adds_up_small_mcao, with the MAP reconstructor
    result = simulate(small(reconstructor="map"), 0.15, seed=1, progress=False,
                      budget_every=2)
    b = result.budget
    assert result.closure_index is not None
    assert b.frames.min() >= result.closure_index
    assert np.all(b.fitting > 0) and np.all(b.temporal > 0) and np.all(b.noise > 0)
    np.testing.assert_allclose(b.total, b.measured, rtol=0.15)


def _polc_case(random_problem):
    g, noise, prior = random_problem
    r = map_reconstructor(g, noise * 30.0, prior)  # low SNR: R G far from 1
    return r @ g, np.random.default_rng(5).standard_normal(g.shape[1])


def test_pseudo_open_loop_control_converges_to_the_map_estimate(random_problem):
    rg, phi = _polc_case(random_problem)
    assert np.abs(rg - np.eye(len(phi))).max() > 0.3
    kw = dict(gain=0.5, leak=0.0, delay_frames=0.5, integration_frames=1.0)
    polc = Controller(len(phi), sensed=rg, **kw)
    plain = Controller(len(phi), **kw)
    mirror = np.zeros(len(phi))
    history = [np.zeros(len(phi))] * 3
    for _ in range(200):
        seen = polc.seen_commands()
        measured = rg @ (phi - seen)  # the reconstruction of the closed-loop slopes
        command, pol, _ = polc.step(measured)
        # the law written out: c_k = c_{k-1} + g (m_k + R G seen - seen)
        expected = history[0] + 0.5 * (measured + rg @ seen - seen)
        np.testing.assert_allclose(command, expected, rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(pol, rg @ phi, rtol=1e-12, atol=1e-12)
        history = [command] + history[:-1]
        mirror = plain.step(rg @ (phi - plain.seen_commands()))[0]
    np.testing.assert_allclose(command, rg @ phi, rtol=1e-9, atol=1e-12)
    # the plain integrator aims at phi itself (R G c = R G phi: weighted least squares),
    # not at the MAP estimate
    assert np.abs(mirror - rg @ phi).max() > 1e-3
    with pytest.raises(ValueError, match="`sensed` must be a finite"):
        Controller(len(phi), sensed=rg[:-1], **kw)


def test_identity_sensing_is_the_classic_integrator(random_problem):
    rg, phi = _polc_case(random_problem)
    kw = dict(gain=0.4, leak=0.01, delay_frames=1.0, integration_frames=1.0)
    a = Controller(len(phi), sensed=np.eye(len(phi)), **kw)
    b = Controller(len(phi), **kw)
    for k in range(20):
        m = np.sin(k + np.arange(len(phi)))
        np.testing.assert_allclose(a.step(m)[0], b.step(m)[0], rtol=1e-12, atol=1e-15)


def test_the_loop_model_gives_the_controller_r_g_only_with_the_map(cut_case):
    # R G of the closed form (numpy.linalg.solve on the normal equations), within its
    # own rounding as in the test of R above (the model forms it from (W^T W + 1)^-1)
    cfg, model, truncated = cut_case
    assert truncated.sensed_commands is None
    g = _interaction(model)
    prior = _prior(cfg, model)
    expected = _closed_form(g, _noise(cfg, model, g, prior), prior) @ g
    np.testing.assert_allclose(model.sensed_commands, expected, rtol=1e-7,
                               atol=1e-9 * np.abs(expected).max())


@pytest.fixture(scope="module")
def map_loop():
    cfg = small(reconstructor="map")
    model = LoopModel(cfg)
    return cfg, model, simulate(cfg, 0.08, seed=5, model=model, progress=False)


def test_persistence_keeps_the_map_loops_bits(map_loop):
    cfg, model, reference = map_loop
    persistence = PersistencePredictor(horizon=3).fit(training_data(reference))
    run = simulate(cfg, 0.08, seed=5, model=model, predictor=persistence, progress=False)
    np.testing.assert_array_equal(run.residual_variance, reference.residual_variance)
    assert run.predictor == "PersistencePredictor"


def test_a_rotated_control_basis_is_the_same_map_loop(map_loop):
    # every mode controlled in rotated coordinates Q: the controller gets Q^T R G Q, and
    # the loop is the same up to rounding
    cfg, model, reference = map_loop
    q, _ = np.linalg.qr(np.random.default_rng(1).standard_normal((model.n_modes,) * 2))
    run = simulate(cfg, 0.08, seed=5, model=model, progress=False, control_basis=q)
    np.testing.assert_allclose(run.residual_variance, reference.residual_variance,
                               rtol=1e-8)


def test_rtc_timing_runs_the_map_loops_pseudo_open_loop_term(cut_case, monkeypatch):
    # reference: the loop's own controller law (POL = m + B^T R G B seen, Ellerbroek &
    # Vogel 2003): the timed step must do that work with a MAP, and none without it
    from closedloop.studies import compression

    _, model, truncated = cut_case
    seen = []
    real = compression.Controller

    def record(*args, **kwargs):
        seen.append(kwargs.get("sensed"))
        return real(*args, **kwargs)

    monkeypatch.setattr(compression, "Controller", record)
    basis = np.eye(model.n_modes)[:, :5]
    compression.rtc_compute_time(model, basis, repeats=2, batches=1)
    compression.rtc_compute_time(truncated, basis, repeats=2, batches=1)
    # the model's R G is formed from (W^T W + 1)^-1, not as the product: equal within
    # the rounding of the two forms (as in the test of sensed_commands above)
    expected = basis.T @ model.reconstructor @ _interaction(model) @ basis
    np.testing.assert_allclose(seen[0], expected, rtol=1e-7,
                               atol=1e-9 * np.abs(expected).max())
    assert seen[1] is None
