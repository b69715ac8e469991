"""The ``kaos`` preset and the shipped closed-loop log ``data/kaos_closedloop.npz``.

References: the shared servo model's 0 dB rejection bandwidth (``modalinfo.servo``,
130 Hz for the documented gain); the paper's KAOS numbers (36 subapertures, Z2-Z28,
D = 0.7 m); and a round trip: the log regenerates bit for bit from its recorded
provenance on the platform and library versions that wrote it (to 1e-9 rad elsewhere,
where FFT/BLAS rounding may differ in the last bits).
"""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from closedloop import LoopModel, presets
from modalinfo.io import load
from modalinfo.servo import closed_loop_bandwidth

DATA = Path(__file__).resolve().parents[2] / "data"


def _make_data():
    spec = importlib.util.spec_from_file_location("make_data", DATA / "make_data.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_kaos_preset_is_the_documented_system():
    cfg = presets.get("kaos")
    bw = closed_loop_bandwidth(rate=1 / cfg.loop.time_step, gain=cfg.loop.gain,
                               delay_frames=cfg.loop.delay_frames,
                               integration_frames=cfg.loop.integration_frames)
    assert bw.rejection_0db == pytest.approx(presets.KAOS_BANDWIDTH, abs=0.5)
    assert cfg.d_over_r0 == pytest.approx(10.0)
    assert cfg.telescope.diameter == 0.7 and cfg.dms[0].n_modes == 27
    model = LoopModel(cfg)
    assert model.dms[0].modes == list(range(2, 29))
    # the paper's 36 subapertures: 7 across, 37 at least half lit
    assert model.wfss[0].n_valid_subapertures in (36, 37)


@pytest.fixture(scope="module")
def make_data():
    return _make_data()


def test_shipped_kaos_closedloop_log_regenerates(make_data):
    shipped = load(DATA / make_data.KAOS_CLOSEDLOOP)
    fresh = make_data.kaos_closedloop()
    assert shipped.shape == fresh.shape == (8000, 27)
    env = make_data.ENVIRONMENT_KEY
    same_env = shipped.metadata[env] == make_data.environment()
    if same_env:
        assert np.array_equal(np.asarray(shipped.coeffs), np.asarray(fresh.coeffs))
    else:
        np.testing.assert_allclose(shipped.coeffs, fresh.coeffs, rtol=0, atol=1e-9)
    strip = {k: v for k, v in shipped.metadata.items() if k != env}
    assert strip == {k: v for k, v in fresh.metadata.items() if k != env}
    assert shipped.rate == 2000.0 and shipped.units == "rad" and shipped.wavelength == 5e-7
    prov = shipped.metadata["provenance"]
    assert prov["preset"] == "kaos" and prov["discarded_frames"] == make_data.KAOS_DISCARD
    assert shipped.metadata["config"] == presets.get("kaos").to_dict()
    assert shipped.metadata["seed"] == make_data.SEED


def test_kaos_closedloop_log_is_a_closed_loop(make_data):
    # a closed loop with 130 Hz rejection bandwidth removes most of the turbulence: the
    # residual is far below the open-loop Noll variance of Z2-Z28 at D/r0 = 10
    from modalinfo.bases import noll_residual_variance

    log = load(DATA / make_data.KAOS_CLOSEDLOOP)
    open_loop = (noll_residual_variance(1) - noll_residual_variance(28)) * 10.0 ** (5 / 3)
    total = float(np.sum(np.var(np.asarray(log.coeffs), axis=0)))
    assert total < 0.01 * open_loop
