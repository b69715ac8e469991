"""Open-loop mode (``loop.closed = false``): the logs hold the turbulence the WFS sees.

References:
- Noll (1976) / von Karman Zernike variances (``modalinfo.bases.zernike_covariance``,
  itself tested against Noll's table and a direct integral) times ``(D/r0)**(5/3)``, for
  the modal turbulence an ideal sensor measures in open loop; the tolerance is computed
  from the number of independent screens (stated at the test);
- linearity: a closed loop's POL is the open-loop modal turbulence (same seed, same
  screens) when the sensor measures the DM's modes exactly (ideal sensor), to float error;
- the definitions: in open loop the residual and POL logs are the same numbers, the
  commands are zero, and the frame-0 measurement of a closed loop (no command applied
  yet) equals the open loop's;
- round trips of the config key through TOML/JSON files and through ``aotpy``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
    load_config,
    save_config,
)
from closedloop.simulation import ORACLE, LoopModel, simulate
from modalinfo.bases import noll_to_zernike, zernike_covariance

D_OVER_R0 = 10.0
L0 = 20.0
N_MODES = 20  # Z2..Z21: radial orders 1..5, complete


def _config(*, closed: bool, wind: float = 0.0, delay: float = 0.0, gain: float = 0.5,
            n_pixels: int = 32, outer_scale: float = L0) -> SimulationConfig:
    return SimulationConfig(
        name="open",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=n_pixels),
        layers=(LayerConfig(altitude=0.0, d_over_r0=D_OVER_R0, wind_speed=wind,
                            wind_direction=30.0, outer_scale=outer_scale),),
        dms=(DMConfig(altitude=0.0, n_modes=N_MODES),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, kind="ideal", field_samples=1),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=delay, gain=gain,
                        closed=closed),
        field=FieldConfig(size=0.0, n_points=1))


def test_open_loop_logs_are_the_turbulence_and_commands_are_zero():
    cfg = _config(closed=False, wind=10.0)
    r = simulate(cfg, 0.01, seed=3, progress=False)
    np.testing.assert_array_equal(r.logs["dm0.pol"].coeffs, r.logs["dm0.residual"].coeffs)
    assert not np.any(r.logs["dm0.commands"].coeffs)
    assert np.all(r.logs["dm0.pol"].coeffs.std(axis=0) > 0)
    # no closure is claimed: the statistics are the turbulence's from frame 0
    assert r.open_loop and r.closure_index == 0
    s = r.summary()
    assert s["open_loop"] is True and math.isnan(s["closure_time_s"])
    assert s["strehl_peak_mean"] == pytest.approx(float(r.strehl_peak.mean()), rel=1e-15)
    closed = simulate(_config(closed=True, wind=10.0), 0.01, seed=3, progress=False)
    assert not closed.open_loop and closed.summary()["open_loop"] is False
    # frame 0 of the closed loop is measured before any command reaches the DM
    np.testing.assert_array_equal(closed.logs["dm0.residual"].coeffs[0],
                                  r.logs["dm0.residual"].coeffs[0])
    # the uncorrected residual is larger than the corrected one after a few frames
    assert r.residual_variance[5:].mean() > 3.0 * closed.residual_variance[5:].mean()


def test_closed_loop_pol_equals_the_open_loop_turbulence():
    # an ideal sensor measures its DM's modes exactly (R G = I) and everything is linear,
    # so POL = measured residual + commands seen during the exposure = the open-loop
    # measurement of the same screens; a half-frame delay makes the command change in
    # the middle of the exposure (two internal steps per frame)
    kw = dict(wind=15.0, delay=0.5e-3, gain=0.4)
    openl = simulate(_config(closed=False, **kw), 0.03, seed=7, progress=False)
    closed = simulate(_config(closed=True, **kw), 0.03, seed=7, progress=False)
    truth = openl.logs["dm0.pol"].coeffs
    pol = closed.logs["dm0.pol"].coeffs
    assert np.abs(closed.logs["dm0.commands"].coeffs).max() > 0.1 * np.abs(truth).max()
    # float error: each POL is a sum of a few terms of the size of the coefficients
    np.testing.assert_allclose(pol, truth, rtol=0, atol=1e-10 * np.abs(truth).max())


def test_open_loop_mode_variances_are_von_karmans():
    # N independent screens (one frame each, a new seed each), an ideal sensor on Z2..Z21.
    # For a zero-mean Gaussian coefficient the mean square over N samples has a relative
    # standard error sqrt(2 / N). Per radial order n (n + 1 modes, uncorrelated with each
    # other in Noll's covariance) the summed mean square has sqrt(2 / (N (n + 1))); the
    # mean over all 20 modes of the ratio to theory has at most sqrt(2 / N) * sqrt(c / 20),
    # c <= 2 allowing for the correlation of same-m modes (Z2-Z8, Z4-Z11, ...). Tolerance:
    # 4 standard errors plus 3 % for the pixel sampling of the 32-pixel pupil (the mean
    # ratio was 0.98 over 1000 screens).
    n_screens = 240
    cfg = _config(closed=False)
    model = LoopModel(cfg)
    coeffs = np.array([simulate(cfg, 1e-3, seed=s, model=model, progress=False)
                       .logs["dm0.pol"].coeffs[0] for s in range(n_screens)])
    modes = list(range(2, N_MODES + 2))
    expected = np.diag(zernike_covariance(modes, outer_scale=L0, diameter=4.0)) * (
        D_OVER_R0 ** (5.0 / 3.0))
    ratio = (coeffs ** 2).mean(axis=0) / expected
    se_all = math.sqrt(2.0 / n_screens) * math.sqrt(2.0 / N_MODES)
    assert ratio.mean() == pytest.approx(1.0, abs=4.0 * se_all + 0.03)
    radial = np.array([noll_to_zernike(j)[0] for j in modes])
    for n in range(1, 6):
        sel = radial == n
        assert sel.sum() == n + 1
        got = (coeffs[:, sel] ** 2).mean(axis=0).sum() / expected[sel].sum()
        se = math.sqrt(2.0 / (n_screens * (n + 1)))
        assert got == pytest.approx(1.0, abs=4.0 * se + 0.03), n


def test_open_loop_key_validates_and_round_trips(tmp_path):
    cfg = _config(closed=False)
    assert cfg.to_dict()["loop"]["closed"] is False
    for fmt in ("toml", "json"):
        path = save_config(cfg, tmp_path / f"open.{fmt}")
        assert load_config(path) == cfg
    # a closed loop's plain form is the one written before the key existed
    assert "closed" not in _config(closed=True).to_dict()["loop"]
    assert SimulationConfig.from_dict(_config(closed=True).to_dict()).loop.closed is True
    with pytest.raises(TypeError, match=r"`loop.closed` must be a bool.*got 'no'"):
        SimulationConfig.from_dict({**cfg.to_dict(), "loop": {"closed": "no"}})
    with pytest.raises(TypeError, match=r"`loop.closed` must be a bool.*got 0"):
        LoopConfig(closed=0)._validate("loop.")


@pytest.mark.parametrize("kwargs,match", [
    ({"predictor": ORACLE}, "`predictor` must be None in open loop.*got 'oracle'"),
    ({"budget_every": 5}, "`budget_every` must be None in open loop.*got 5"),
    ({"control_basis": np.eye(N_MODES)}, "`control_basis` must be None in open loop.*ndarray"),
])
def test_open_loop_refuses_what_needs_commands(kwargs, match):
    with pytest.raises(ValueError, match=match):
        simulate(_config(closed=False), 2e-3, progress=False, **kwargs)


def test_open_loop_aot_export_says_open(tmp_path):
    aotpy = pytest.importorskip("aotpy")
    from closedloop.aot import export_aot

    r = simulate(_config(closed=False, wind=5.0), 5e-3, seed=1, progress=False)
    system = aotpy.AOSystem.read_from_file(export_aot(r, tmp_path / "open.fits"))
    loops = [lp for lp in system.loops if lp.uid.startswith("dm0")]
    assert loops and all(lp.closed is False for lp in loops)


def test_open_loop_cli_line_and_saved_result(tmp_path, capsys):
    from closedloop.cli import main
    from closedloop.result import SimulationResult

    path = save_config(_config(closed=False, wind=5.0), tmp_path / "open.toml")
    out = tmp_path / "open.h5"
    assert main(["run", "--config", str(path), "--duration", "0.005", "--seed", "2",
                 "--out", str(out), "--quiet"]) == 0
    line = capsys.readouterr().out.strip()
    assert "in open loop (no correction)" in line and "closure" not in line
    # Noll: 1.03 (D/r0)^(5/3) rad^2 >> 1.2 rad^2, where exp(-sigma^2) is no image's Strehl
    # (test_physics: within 0.05 of the FFT-PSF Strehl only above SR 0.3): said on the line
    assert 1.03 * D_OVER_R0 ** (5 / 3) > 1.2
    assert line.endswith("note: SR = exp(-sigma^2) (Marechal) is below 0.3, where it is no "
                         "longer the image's Strehl ratio (it underestimates it; "
                         "docs/CLOSEDLOOP.md)")
    saved = SimulationResult.load(out)
    assert saved.open_loop and saved.config == _config(closed=False, wind=5.0)
