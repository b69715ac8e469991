"""Controlled modes the WFS cannot see are counted, warned at set-up and named (fixes 47-d).

Round 47 PART a, Z06: 2,900 modes of a 61 x 61 actuator DM on a 48 x 48 Shack-Hartmann
pass the modes <= slopes rule; the loop sat at SR 0.001 and ``loop_status`` said only
"did not close ... swings too widely", without the cause: the interaction matrix is
rank-deficient in the controlled-mode space, and the reconstructor's pseudo-inverse drops
the directions below ``rcond`` (1e-3) times its largest singular value.
Reference: numpy's own rank of the same interaction matrix,
``M - numpy.linalg.matrix_rank(G, tol=1e-3 * s_max)`` (a 12 x 12 actuator DM, 60 modes,
on 6 x 6 subapertures: 56 slopes, rank 54; G weighted by the slopes' light share as the
reconstructor weighs it, the same count unweighted), and ``numpy.linalg.pinv`` for the
reconstructor, unchanged to the bit. A DM of 20 modes on the same WFS (full rank)
does not warn.
"""

import dataclasses
import warnings

import numpy as np
import pytest

from closedloop import simulate
from closedloop.config import SimulationConfig
from closedloop.model import LoopModel
from closedloop.result import SimulationResult

RCOND = 1e-3  # the WFS's default cut (closedloop.optics.wfs.WavefrontSensor)

CFG = {
    "name": "unseen", "seed": 0, "wavelength": 6.3e-07, "r0_wavelength": 5e-07,
    "telescope": {"diameter": 1.0, "obscuration": 0.0, "zenith_angle": 0.0, "n_pixels": 48},
    "loop": {"time_step": 0.002, "integration_time": 0.002, "delay": 0.0005, "gain": 0.5,
             "leak": 0.0, "model_error": 0.3},
    "field": {"size": 0.0, "n_points": 1},
    "layers": [{"altitude": 0.0, "d_over_r0": 8.0, "wind_speed": 5.0,
                "wind_direction": 0.0, "outer_scale": 20.0}],
    "dms": [{"altitude": 0.0, "n_modes": 60, "kind": "actuators", "n_actuators": 12,
             "coupling": 0.35, "threshold": 0.05}],
    "wfss": [{"altitude": 0.0, "field_of_view": 0.0, "n_subapertures": 6, "noise": 0.0,
              "kind": "shack_hartmann", "field_samples": 1, "dm": 0}],
}


def _config(n_modes: int) -> SimulationConfig:
    return SimulationConfig.from_dict({**CFG, "dms": [{**CFG["dms"][0], "n_modes": n_modes}]})


def _numpy_unseen(g: np.ndarray) -> int:
    s = np.linalg.svd(g, compute_uv=False)
    return g.shape[1] - int(np.linalg.matrix_rank(g, tol=RCOND * s[0]))


def _unseen_warnings(caught) -> list[str]:
    return [str(w.message) for w in caught if "unseen by the WFS" in str(w.message)]


def test_unseen_count_is_numpys_rank_deficit_and_warned_once():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = LoopModel(_config(60))
    wfs = model.wfss[0]
    g = np.asarray(wfs.interaction)
    # the reconstructor weighs each slope by its inverse noise variance (its edge
    # subaperture's light share): (S^1/2 G)^+ S^1/2
    root = np.sqrt(wfs._inverse_variance_weights())[:, None] if wfs._weighted else 1.0
    expected = _numpy_unseen(root * g)
    assert expected == _numpy_unseen(g) > 0  # 6: exact null directions (s ~ 1e-13 s_max)
    assert model.unseen_modes == wfs.unseen_modes == expected
    said = _unseen_warnings(caught)
    assert len(said) == 1, said
    assert f"{expected} controlled modes" in said[0]
    assert f"{expected} of its 60 modes" in said[0] and "rcond = 0.001" in said[0]
    assert "fewer modes" in said[0] and "finer WFS" in said[0]
    # the count's SVD replaces numpy.linalg.pinv's: the same reconstructor to the bit
    pinv = np.linalg.pinv(root * g, rcond=RCOND)
    np.testing.assert_array_equal(wfs.reconstructor, pinv if np.isscalar(root)
                                  else pinv * root.T)


def test_few_modes_do_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)
        model = LoopModel(_config(20))
    assert _numpy_unseen(np.asarray(model.wfss[0].interaction)) == 0
    assert model.unseen_modes == 0


@pytest.fixture(scope="module")
def run():
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", "[0-9]+ controlled modes? unseen", UserWarning)
        return simulate(_config(60), 0.02, progress=False)


def test_status_of_a_loop_that_did_not_close_names_the_unseen_modes(run):
    n = run.unseen_modes
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        g = np.asarray(LoopModel(run.config).wfss[0].interaction)
    assert n == _numpy_unseen(g) > 0  # the count rides on the result
    # the run's residual held at its open-loop level: a loop that did not close
    flat = dataclasses.replace(run, residual_variance=np.repeat(
        run.residual_variance[:1], run.residual_variance.shape[0], axis=0))
    status = flat.loop_status
    assert status.startswith("did not close"), status
    assert f"{n} controlled modes unseen by the WFS" in status, status
    # the same without unseen modes: the verdict alone
    plain = dataclasses.replace(flat, unseen_modes=0).loop_status
    assert "unseen" not in plain and status.startswith(plain)


def test_unseen_count_saved_and_loaded(run, tmp_path):
    back = SimulationResult.load(run.save(tmp_path / "r.h5"))
    assert back.unseen_modes == run.unseen_modes and isinstance(back.unseen_modes, int)
    assert back == run and back.loop_status == run.loop_status
