"""A predictor fitted on a run's AOT export knows the run's conditions (fix57-d, X48).

Round 55 PART b, X48: ``linear-ls`` fitted on ``modalinfo.io.load(export.fits,
loop="dm0.pol")`` ran in a loop at another r0 without a word, where the same fit on the
run's in-memory POL is refused (fix54-b): the log read from the export had no config,
so ``closedloop.control.predictors.fitted_conditions`` knew nothing. ``closedloop
export`` writes the run's config as TOML in the system's ``config`` (aotpy's
``AOSystem.config``); the AOT reader now gives it back as ``metadata["config"]`` with
``source`` "closedloop".

References: the run's own ``SimulationConfig.to_dict`` and the log of its run.h5 (the
metadata a run.h5 log carries, ``SimulationResult.save`` then ``modalinfo.io.load``);
the refusal of the same fit on the in-memory POL (fix54-b's check); aotpy's reader on the
same file; a file whose config aotpy leaves empty (as another writer's) keeps the old
behaviour (no config, the rate / units checks of round 55 only).
"""

import dataclasses
import json

import numpy as np
import pytest

pytest.importorskip("aotpy")

from closedloop import simulate  # noqa: E402
from closedloop.aot import export_aot  # noqa: E402
from closedloop.control.predictors import fitted_conditions  # noqa: E402
from modalinfo.forecast import make_predictor  # noqa: E402
from modalinfo.io import load  # noqa: E402

from .conftest import lag_only  # noqa: E402


@pytest.fixture(scope="module")
def ref(tmp_path_factory):
    cfg = lag_only()
    run = simulate(cfg, 0.12, seed=0)
    folder = tmp_path_factory.mktemp("export_config")
    return cfg, run, export_aot(run, folder / "run.fits", mode_images=False), folder


def _stronger(cfg):
    """The same loop at 1.5 times the D/r0 (X48: 2x on kaos; 2x here is below a pixel)."""
    return cfg.replace(layers=tuple(dataclasses.replace(lay, d_over_r0=1.5 * lay.d_over_r0)
                                    for lay in cfg.layers))


def test_export_gives_back_the_runs_config(ref):
    cfg, run, path, folder = ref
    h5 = run.save(folder / "run.h5")
    for loop in ("dm0", "dm0.pol"):
        meta = load(path, loop=loop).metadata
        assert meta["source"] == "closedloop"
        assert meta["config"] == cfg.to_dict()
        # the same dict as the run.h5 log's
        name = "dm0.residual" if loop == "dm0" else loop
        assert meta["config"] == load(h5, dataset=f"logs/{name}").metadata["config"]


def test_export_fitted_predictor_refused_at_another_r0(ref):
    cfg, run, path, _ = ref
    stronger = _stronger(cfg)
    bare = make_predictor("linear-ls").fit(load(path, loop="dm0.pol"))
    assert fitted_conditions(bare) is not None
    with pytest.raises(ValueError, match=r"`layers` is not this config's"):
        simulate(stronger, 0.01, predictor=bare, seed=1)
    # the same refusal as the same fit on the run's in-memory POL (X49)
    memory = make_predictor("linear-ls").fit(run.logs["dm0.pol"])
    with pytest.raises(ValueError, match=r"`layers` is not this config's"):
        simulate(stronger, 0.01, predictor=memory, seed=1)


def test_export_fitted_predictor_runs_in_its_conditions(ref):
    cfg, _, path, _ = ref
    bare = make_predictor("linear-ls").fit(load(path, loop="dm0.pol"))
    other = cfg.replace(loop=dataclasses.replace(cfg.loop, gain=0.3))  # the controller only
    r = simulate(other, 0.01, predictor=bare, seed=1)
    assert np.all(np.isfinite(r.strehl))


def test_aotpy_reads_the_export_and_its_arrays(ref):
    import aotpy

    _, run, path, _ = ref
    system = aotpy.AOSystem.read_from_file(str(path))
    loop = next(lp for lp in system.loops if lp.uid == "dm0.pol")
    np.testing.assert_array_equal(loop.modal_coefficients.data, run.logs["dm0.pol"].coeffs)


def _rewritten(path, out, config):
    """The export with its system config replaced (aotpy writes it back as it reads it)."""
    import aotpy

    system = aotpy.AOSystem.read_from_file(str(path))
    system.config = None if config is None else json.dumps(config)  # as build_system quotes it
    system.write_to_file(str(out))
    return out


def test_export_without_a_config_keeps_the_old_behaviour(ref):
    cfg, _, path, folder = ref
    bare_path = _rewritten(path, folder / "no_config.fits", None)
    meta = load(bare_path, loop="dm0.pol").metadata
    assert "config" not in meta and "source" not in meta
    bare = make_predictor("linear-ls").fit(load(bare_path, loop="dm0.pol"))
    assert fitted_conditions(bare) is None
    r = simulate(_stronger(cfg), 0.01, predictor=bare, seed=1)  # as before: unknown
    assert np.all(np.isfinite(r.strehl))
    # and round 55's rate check still refuses it at twice its rate (X50)
    faster = cfg.replace(loop=dataclasses.replace(cfg.loop, time_step=5e-4,
                                                  integration_time=5e-4))
    with pytest.raises(ValueError, match=r"fitted on frames at 1000 Hz; the loop's POL .* is "
                                         r"at 2000 Hz"):
        simulate(faster, 0.01, predictor=bare, seed=1)


def test_unreadable_or_foreign_config_is_left_out(ref):
    _, _, path, folder = ref
    broken = _rewritten(path, folder / "broken.fits", 'name = ')
    assert "config" not in load(broken, loop="dm0.pol").metadata


def test_config_of_another_version_is_named(ref):
    _, _, path, folder = ref
    old = _rewritten(path, folder / "old.fits", 'name = "x"\nnot_a_key = 1\n')
    bare = make_predictor("linear-ls").fit(load(old, loop="dm0.pol"))
    with pytest.raises(ValueError, match=r"fitted on a closedloop log whose run config this "
                                         r"version does not read \(.*not_a_key"):
        fitted_conditions(bare)
