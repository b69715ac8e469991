"""A bare Predictor fitted on a log unlike the loop's POL is refused (round 55 PART b).

Reference: what ``closedloop.simulate`` feeds a predictor, by its own definition
(``SimulationResult.from_run`` and docs/CLOSEDLOOP.md): the pseudo-open-loop (POL)
coefficients of every DM, in rad at ``r0_wavelength``, one frame per
``loop.time_step``, in the DMs' mode order. Round 55 PART b measured on the kaos preset
(0.4 s, seeds 1-3): a ``linear-ls`` fitted on the run's residual log gave SR peak 0.004
to 0.02 against 0.56-0.61 fitted on the POL, one fitted on the POL in nm 0.26-0.29, an
ARMA in nm 0.49-0.54, all without a word (X43, X45, X46); one fitted on the run's AOT
export (whose metadata holds no config, so fix54-b's conditions are unknown) ran at
twice its frame rate (X50). A predictor fitted on the POL itself runs (the control).
"""

import dataclasses

import numpy as np
import pytest

from closedloop import simulate
from closedloop.aot import export_aot
from modalinfo.forecast import make_predictor
from modalinfo.io import load

from .conftest import lag_only


@pytest.fixture(scope="module")
def ref():
    cfg = lag_only()
    return cfg, simulate(cfg, 0.12, seed=0)


def test_pol_fitted_runs(ref):
    cfg, run = ref
    bare = make_predictor("linear-ls").fit(run.logs["dm0.pol"])
    r = simulate(cfg, 0.01, predictor=bare, seed=1)
    assert np.all(np.isfinite(r.strehl))


@pytest.mark.parametrize("quantity", ["residual", "commands"])
def test_other_series_refused(ref, quantity):
    cfg, run = ref
    bare = make_predictor("linear-ls").fit(run.logs[f"dm0.{quantity}"])
    with pytest.raises(ValueError, match=rf"fitted on a run's {quantity} log, but the loop "
                                         r"feeds it the pseudo-open loop"):
        simulate(cfg, 0.01, predictor=bare, seed=1)


def test_units_and_wavelength_refused(ref):
    cfg, run = ref
    pol = run.logs["dm0.pol"]
    nm = make_predictor("arma").fit(pol.to_units("nm"))
    with pytest.raises(ValueError, match=r"fitted on a log in nm; the loop's POL .* is in rad"):
        simulate(cfg, 0.01, predictor=nm, seed=1)
    at600 = make_predictor("linear-ls").fit(pol.to_units("nm").to_units("rad", wavelength=6e-7))
    with pytest.raises(ValueError, match=r"fitted on phase \[rad\] at 6e-07 m; the loop's "
                                         r"POL .* is phase at 5e-07 m"):
        simulate(cfg, 0.01, predictor=at600, seed=1)


def test_mode_order_refused(ref):
    cfg, run = ref
    pol = run.logs["dm0.pol"]
    reversed_ = make_predictor("linear-ls").fit(pol.select(modes=pol.labels[::-1]))
    with pytest.raises(ValueError, match=r"fitted on modes \(.*\) but the loop feeds it"):
        simulate(cfg, 0.01, predictor=reversed_, seed=1)


def test_aot_export_rate_refused(ref, tmp_path):
    cfg, run = ref
    path = export_aot(run, tmp_path / "run.fits", mode_images=False)
    bare = make_predictor("linear-ls").fit(load(path, loop="dm0.pol"))
    # the config is read back since fix57-d (it was absent: fix54-b could not apply, X48)
    assert bare.training_metadata_["config"] == cfg.to_dict()
    faster = cfg.replace(loop=dataclasses.replace(cfg.loop, time_step=5e-4,
                                                  integration_time=5e-4))
    # refused by the run's conditions first since fix57-d; the rate check (X50) of an
    # export without a config: test_export_config_fix57d.py
    with pytest.raises(ValueError, match=r"`loop.time_step` is not this config's \(0.001 vs "
                                         r"0.0005\)"):
        simulate(faster, 0.01, predictor=bare, seed=1)
    residual = make_predictor("linear-ls").fit(load(path, loop="dm0"))
    with pytest.raises(ValueError, match=r"fitted on a run's residual log"):
        simulate(cfg, 0.01, predictor=residual, seed=1)
    r = simulate(cfg, 0.01, predictor=bare, seed=1)  # the export's POL, same loop: runs
    assert np.all(np.isfinite(r.strehl))
