"""The error budget's bookkeeping and its terms in the cases test_laws_budget.py leaves out.

References (outside the budget's code):
- Temporal term with prediction: in a loop whose only error is the servo lag (ideal
  sensor, zonal "ideal" DM, no noise, one ground layer; test_laws_budget.py), the
  temporal term must equal the residual the real loop left (its science camera, an
  independent path from the budget's copy of the controller) also when the loop forecasts:
  with the oracle (the true future) and with a fitted linear predictor. The three runs
  must differ from one another (a copy of the controller that dropped the forecast would
  give the no-prediction residual, not the run's).
- Noise term with one reconstructor per WFS: three DMs (a zonal one, whose ideal sensor
  is noise-free, and two modal ones at 4 and 8 km with Shack-Hartmann sensors of
  different noise), so the command covariance is block-diagonal,
  ``ntf sum_j sigma_j^2 R_j R_j^T`` placed on DM j's modes (R_j: WFS j's own
  reconstructor, the matrix the loop applies), seen on axis as ``tr(Gram C)`` over the
  pupil with the modes' piston-removed inner products (written here);
  ``ntf = g (1 + g) / ((1 - g) (2 + g))`` for a one-frame delay (Box & Jenkins,
  derived in test_laws_budget.py), ``sigma_j = 2 pi alpha_j [rad] / r0_wavelength``.
- Fitting term with a field: a fitting-only loop (static turbulence, gain 1, no delay)
  whose ideal WFS averages a 5-km layer over 7 field samples: the fitting term must be
  the real loop's residual (as in test_laws_budget.py), which holds only if the budget's
  ideal sensors keep the WFS's field samples.
- The temporal term's controller: driven by the same residuals as the loop's own
  controller (built by the simulation, with a fitted predictor, on two modal DMs whose
  joint reconstructor's ``R G`` is not the identity), it must give the same commands bit
  for bit (the docstring's "a copy of the controller (same gain, delay, predictor)").
- Seeds: the project's rule "same seed -> same bits" (the noise term is a seeded
  Monte-Carlo average).
- Frames kept: the documented contract of ``BudgetProbe.result`` (the probed frames from
  ``start`` on, all of them when none is; each term the mean over those frames, times the
  science scale), recomputed here from rows written by hand.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from closedloop import ORACLE
from closedloop import budget as budget_module
from closedloop.budget import BudgetProbe
from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.model import LoopModel
from closedloop.simulation import _Control, simulate
from modalinfo.forecast import LinearPredictor

from .conftest import lag_only
from .test_laws_budget import _mcao_noise_config

# negligible turbulence on purpose (D/r0 = 1e-6, a total r0 of 4000 km): the loop sees
# its noise only
pytestmark = pytest.mark.filterwarnings("ignore:`total r0 .* is beyond 1 m at 500 nm:UserWarning")

ARCSEC = math.pi / 648000.0
N_DRAWS_ZONAL = 512


@pytest.fixture(scope="module")
def lag_model():
    return LoopModel(lag_only())


def test_temporal_term_of_a_forecasting_loop_is_its_residual(lag_model):
    cfg = lag_model.config
    rng = np.random.default_rng(0)
    # a fitted AR predictor (its running state matters): fitted on random walks
    history = 0.01 * rng.standard_normal((300, lag_model.n_modes)).cumsum(axis=0)
    linear = LinearPredictor(horizon=2).fit(history)
    runs = {}
    for name, pred in (("none", None), ("oracle", ORACLE), ("linear", linear)):
        b = simulate(cfg, 0.03, seed=1, progress=False, model=lag_model, predictor=pred,
                     budget_every=1).budget
        assert b.frames.size >= 10
        np.testing.assert_allclose(b.temporal, b.measured, rtol=1e-9, err_msg=name)
        runs[name] = float(b.temporal[0])
    # the forecasts change the residual (else this test could not see them dropped)
    assert runs["oracle"] < 0.5 * runs["none"]
    assert abs(runs["linear"] / runs["none"] - 1.0) > 0.05


def _noise_config() -> SimulationConfig:
    return SimulationConfig(
        name="noise-blocks",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=32),
        layers=(LayerConfig(altitude=0.0, d_over_r0=1e-6, wind_speed=0.0),),
        dms=(DMConfig(altitude=0.0, n_modes=20, kind="ideal"),
             DMConfig(altitude=4000.0, n_modes=9), DMConfig(altitude=8000.0, n_modes=14)),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, kind="ideal", noise=0.0,
                        n_subapertures=8, field_samples=1, dm=0),
              WFSConfig(altitude=4000.0, field_of_view=0.0, n_subapertures=6, noise=0.02,
                        field_samples=1, dm=1),
              WFSConfig(altitude=8000.0, field_of_view=0.0, n_subapertures=5, noise=0.01,
                        field_samples=1, dm=2)),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=1e-3, gain=0.4),
        field=FieldConfig(size=0.0, n_points=1), wavelength=630e-9, r0_wavelength=500e-9)


def _on_axis_modes(model, dm_index):
    """DM ``dm_index``'s modes on the pupil pixels seen on axis, ``(n_modes, n_pupil)``."""
    g = model.geometry
    dm = model.dms[dm_index]
    plane = g.planes[dm.plane]
    maps = np.zeros((dm.shapes.shape[1], plane.n * plane.n))
    maps[:, dm.pixels] = dm.shapes.T
    maps = maps.reshape(-1, plane.n, plane.n)
    off = plane.centre - (g.n_pixels - 1) / 2.0
    o = int(round(off))
    assert off == o   # whole-pixel read
    return maps[:, o:o + g.n_pixels, o:o + g.n_pixels][:, g.pupil_mask]


def test_noise_term_of_one_reconstructor_per_wfs(monkeypatch):
    # 512 draws, not 4096: each draw multiplies the zonal DM's 835 x 918 reconstructor
    monkeypatch.setattr(budget_module, "_N_NOISE_DRAWS", N_DRAWS_ZONAL)
    cfg = _noise_config()
    model = LoopModel(cfg)
    assert model.reconstructor is None     # a zonal DM: one reconstructor per WFS
    gain = cfg.loop.gain
    ntf = gain * (1 + gain) / ((1 - gain) * (2 + gain))
    pupil, cov = [], []
    for j in (1, 2):
        r = model.wfss[j].reconstructor
        sigma = 2.0 * math.pi * cfg.wfss[j].noise * ARCSEC / cfg.r0_wavelength
        pupil.append(_on_axis_modes(model, j))
        cov.append(ntf * sigma ** 2 * (r @ r.T))
    modes = np.concatenate(pupil)
    modes = modes - modes.mean(axis=1, keepdims=True)
    gram = modes @ modes.T / modes.shape[1]
    c = np.zeros_like(gram)
    n1 = cov[0].shape[0]
    c[:n1, :n1], c[n1:, n1:] = cov
    gc = gram @ c
    expected = float(np.trace(gc)) * (cfg.r0_wavelength / cfg.wavelength) ** 2
    rel_se = math.sqrt(2.0 * np.trace(gc @ gc) / N_DRAWS_ZONAL) / float(np.trace(gc))
    assert rel_se < 0.04
    # the 8-km WFS's share is not negligible (a block put on the wrong columns shows)
    share = float(np.trace(gram[n1:, n1:] @ cov[1])) / float(np.trace(gc))
    print(f"8-km share {share:.3f}, s.e. {rel_se:.2%}")
    assert 0.2 < share < 0.8
    b = simulate(cfg, 0.01, seed=2, progress=False, model=model, budget_every=2).budget
    assert b.noise.shape == (1,)
    print(f"noise term {b.noise[0]:.5g} vs {expected:.5g} rad^2")
    assert b.noise[0] == pytest.approx(expected, rel=4.5 * rel_se)


def test_noise_term_same_seed_same_bits():
    cfg = _noise_config()
    model = LoopModel(cfg)
    a, b, c = (simulate(cfg, 0.01, seed=s, progress=False, model=model,
                        budget_every=2).budget.noise for s in (3, 3, 4))
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)    # the seed reaches the Monte-Carlo draws
    assert np.all(a > 0)


def test_frames_kept_and_science_scale(lag_model):
    n_dir = len(lag_model.science.directions)
    probe = BudgetProbe(lag_model, None, 2)
    frames = [0, 2, 4, 6]
    rows = {name: [np.full(n_dir, float(v)) for v in values] for name, values in
            (("fitting", (1, 2, 3, 5)), ("sh", (2, 4, 7, 13)), ("temporal", (10, 20, 30, 50)))}
    probe.rows = {"frame": frames, **rows}
    measured = np.arange(8.0)[:, None] * np.ones(n_dir)
    scale = 2.5
    for start, kept in ((4, [2, 3]), (3, [2, 3]), (5, [3]), (0, [0, 1, 2, 3]),
                        (7, [0, 1, 2, 3])):   # 7: after the last probe: all frames
        b = probe.result(measured, start, scale, seed=0)
        np.testing.assert_array_equal(b.frames, np.array(frames)[kept])
        fit = np.mean([rows["fitting"][i] for i in kept], axis=0)
        sh = np.mean([rows["sh"][i] for i in kept], axis=0)
        temporal = np.mean([rows["temporal"][i] for i in kept], axis=0)
        np.testing.assert_allclose(b.fitting, scale * fit, rtol=1e-15)
        np.testing.assert_allclose(b.aliasing, scale * (sh - fit), rtol=1e-15)
        np.testing.assert_allclose(b.temporal, scale * temporal, rtol=1e-15)
        np.testing.assert_allclose(b.measured, np.full(n_dir, np.mean([2.0 * i for i in kept])),
                                   rtol=1e-15)
        np.testing.assert_array_equal(b.noise, np.zeros(n_dir))   # a noise-free WFS


def test_fitting_term_keeps_the_wfs_field_samples():
    # a fitting-only loop (static turbulence, gain 1, no delay, ideal sensor, Zernike DM)
    # whose ideal WFS averages a 5-km layer over 7 field samples of a 40" field: the
    # fitting term is the real loop's residual only if the budget's ideal sensors keep
    # those samples (the default is 3)
    cfg = lag_only()
    cfg = cfg.replace(
        layers=(LayerConfig(altitude=0.0, d_over_r0=6.0, wind_speed=0.0),
                LayerConfig(altitude=5000.0, d_over_r0=6.0, wind_speed=0.0)),
        dms=(DMConfig(altitude=0.0, n_modes=20),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=40.0, kind="ideal", noise=0.0,
                        n_subapertures=8, field_samples=7),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=0.0, gain=1.0))
    b = simulate(cfg, 0.02, seed=1, progress=False, budget_every=1).budget
    assert b.frames.size >= 5
    for term in (b.aliasing, b.temporal, b.noise):
        np.testing.assert_array_equal(term, 0.0)
    np.testing.assert_allclose(b.fitting, b.measured, rtol=1e-9)
    # the samples matter: the on-axis sensor fits the on-axis phase better (0.537 against
    # 0.563 rad^2 measured), far beyond the 1e-9 of the law above
    on_axis = cfg.replace(wfss=(WFSConfig(altitude=0.0, field_of_view=40.0, kind="ideal",
                                          noise=0.0, n_subapertures=8, field_samples=1),))
    b1 = simulate(on_axis, 0.02, seed=1, progress=False, budget_every=1).budget
    assert b1.fitting[0] < 0.98 * b.fitting[0]


def test_budget_controller_is_the_loops_controller():
    # the temporal term's copy of the controller must act as the loop's (the gain, delay,
    # predictor and the projector R G that keeps the forecast in the controlled modes):
    # driven by the same residuals, the two give the same commands, bit for bit. Two
    # modal DMs with the joint MAP reconstructor, whose R G is not the identity (it cuts
    # the DM-mode combinations no WFS sees), so a forecast left unprojected shows
    cfg = _mcao_noise_config(0.02, shift_px=8)
    model = LoopModel(cfg)
    projector = model.controlled_projector
    assert np.abs(projector - np.eye(model.n_modes)).max() > 0.1
    rng = np.random.default_rng(3)
    history = rng.standard_normal((200, model.n_modes)).cumsum(axis=0)
    loop_predictor = LinearPredictor(horizon=2).fit(history)
    probe_predictor = LinearPredictor(horizon=2).fit(history)
    probe = BudgetProbe(model, probe_predictor, 1)
    loop = _Control(model, cfg.loop, loop_predictor, None, "raise")
    for _ in range(12):
        m = rng.standard_normal(model.n_modes)
        expected, _ = loop.step(m, None)
        command, _, _ = probe.controller.step(m, None)
        np.testing.assert_array_equal(command, expected)
