"""Controlled modes a joint reconstructor cannot see are counted and named (fixes 48-b).

Fixes 47-d counted the modes the per-WFS least-squares reconstructors drop and left the
joint (several DMs) reconstructor uncounted (``LoopModel.unseen_modes`` None): its own
cut is a signal-to-noise one. The count now is ``M`` less the rank of the truncated
reconstructor's whitened interaction matrix (every WFS with every DM) at rcond 1e-3.
Reference: numpy's ``M - numpy.linalg.matrix_rank(W, tol=1e-3 * s_max)`` of the whitened
``W`` (and of ``LoopModel.interaction`` itself: the same count here), numpy's SVD for
``gram_pinv``'s singular values, and the geometry: two modal DMs (0 and 5 km) seen by two
on-axis WFSs with no field share one disc, so the 5 km DM's 10 modes repeat the ground
DM's first 10 (10 unseen); a 60" field tells them apart (full rank). Not warned at
set-up (the per-WFS count is): the tests' nearly degenerate 6 m DMs
(test_map_reconstructor, test_mutation_gaps_model) leave 2 of 14 modes unseen by design.
"""

import dataclasses
import warnings

import numpy as np
import pytest

from closedloop import simulate
from closedloop.config import SimulationConfig
from closedloop.model import LoopModel, _whitened
from closedloop.optics.products import gram_pinv

from .test_unseen_modes_fixes47 import CFG as SCAO

RCOND = 1e-3

# fixes 47-d's single-DM loop (its telescope, loop and seed) with a second DM and WFS
CFG = {
    **SCAO, "name": "joint-unseen",
    "telescope": {**SCAO["telescope"], "n_pixels": 32},
    "layers": [SCAO["layers"][0],
               {"altitude": 5000.0, "d_over_r0": 3.0, "wind_speed": 15.0,
                "wind_direction": 90.0}],
    "dms": [{"altitude": 0.0, "n_modes": 20}, {"altitude": 5000.0, "n_modes": 10}],
    "wfss": [{"altitude": h, "field_of_view": 0.0, "n_subapertures": 6, "noise": 0.0, "dm": d}
             for d, h in ((0, 0.0), (1, 5000.0))],
}
UNSEEN = "[0-9]+ controlled modes? unseen"


def _config(field: float) -> SimulationConfig:
    return SimulationConfig.from_dict({
        **CFG, "field": {"size": field, "n_points": 1 if field == 0 else 5},
        "wfss": [{**w, "field_of_view": field} for w in CFG["wfss"]]})


def _numpy_unseen(model) -> int:
    """numpy's rank deficit of the whitened W = N^-1/2 G C^1/2 the reconstructor inverts
    (and of G itself, which the whitening's invertible scalings keep here)."""
    w = _whitened(model.interaction, model.noise_variance, model.prior)
    s = np.linalg.svd(w, compute_uv=False)
    g = np.linalg.svd(model.interaction, compute_uv=False)
    out = w.shape[1] - int(np.linalg.matrix_rank(w, tol=RCOND * s[0]))
    assert out == w.shape[1] - int(np.linalg.matrix_rank(model.interaction, tol=RCOND * g[0]))
    return out


def test_joint_unseen_count_is_numpys_rank_deficit_and_not_warned():
    with warnings.catch_warnings():
        # counted, not warned (closedloop/model.py: several DMs' modes no WFS direction
        # tells apart are often harmless; the loop's status names them)
        warnings.filterwarnings("error", UNSEEN, UserWarning)
        model = LoopModel(_config(0.0))
    assert model.reconstructor is not None  # the joint reconstructor
    assert model.unseen_modes == _numpy_unseen(model) == 10


def test_a_field_that_separates_the_dms_sees_every_mode():
    model = LoopModel(_config(60.0))
    assert model.unseen_modes == _numpy_unseen(model) == 0


def test_a_joint_run_carries_the_count_to_its_status():
    run = simulate(_config(0.0), 0.01, progress=False)
    assert run.unseen_modes == 10
    flat = dataclasses.replace(run, residual_variance=np.repeat(
        run.residual_variance[:1], run.residual_variance.shape[0], axis=0))
    status = flat.loop_status
    assert status.startswith("did not close"), status
    assert "10 controlled modes unseen by the WFS" in status, status
    assert "with several DMs, combinations of their modes" in status


@pytest.mark.parametrize("shape", [(40, 12), (12, 40)])
def test_gram_pinv_gives_numpys_singular_values(shape):
    rng = np.random.default_rng(4)
    a = rng.standard_normal(shape)
    _, kept, sv = gram_pinv(a, lambda s0: RCOND * s0, return_sv=True)
    np.testing.assert_allclose(sv, np.linalg.svd(a, compute_uv=False), rtol=1e-10)
    assert kept == 12
