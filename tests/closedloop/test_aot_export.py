"""closedloop runs exported as AO Telemetry (AOT) systems, read back by aotpy and modalinfo.

References: ``aotpy.AOSystem.read_from_file`` itself (an independent reader of the
file), bitwise equality with the ``SimulationResult``'s own arrays, the simulator's
``LoopModel`` (mode shapes, disc pixels, reconstructor) and a matrix product written
here with numpy, analytic values of the atmosphere's description (fractions
``(D/r0_l)^(5/3) / sum``, ``r0 = D / sum^(3/5)``), the TOML text parsed back with
``tomllib``, and the command-line contract (exit 2, one line, files untouched). The
Strehl ratio and its wavelength read back by aotpy (and by astropy from the raw header)
against the run's own summary and config, the loop's time filter against the analytic
leaky integrator ``c_k = (1 - leak) c_{k-1} + gain m_k``.
"""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

aotpy = pytest.importorskip("aotpy")

from closedloop import LoopModel, SimulationConfig, simulate  # noqa: E402
from closedloop.aot import export_aot  # noqa: E402
from closedloop.cli import main as closedloop_main  # noqa: E402
from closedloop.config import DMConfig, WFSConfig  # noqa: E402
from modalinfo.cli import main as modalinfo_main  # noqa: E402
from modalinfo.io import load  # noqa: E402
from modalinfo.io.aot_system import config_of, geometry_of  # noqa: E402

from .conftest import small  # noqa: E402


@pytest.fixture(scope="module")
def cfg():
    return small(leak=0.01)


@pytest.fixture(scope="module")
def model(cfg):
    return LoopModel(cfg)


@pytest.fixture(scope="module")
def run(cfg, model):
    return simulate(cfg, 0.03, seed=4, model=model, progress=False)


@pytest.fixture(scope="module")
def exported(run, model, tmp_path_factory):
    path = tmp_path_factory.mktemp("aot") / "run.fits"
    export_aot(run, path, model=model)
    return path


@pytest.fixture(scope="module")
def system(exported):
    return aotpy.AOSystem.read_from_file(exported)


def _loop(system, uid):
    return next(lp for lp in system.loops if lp.uid == uid)


def _native(image):
    arr = np.asarray(image.data)
    return arr.astype(arr.dtype.newbyteorder("=")) if not arr.dtype.isnative else arr


def test_aotpy_reads_the_results_arrays_bit_for_bit(run, cfg, system):
    assert sorted(lp.uid for lp in system.loops) == [
        "dm0", "dm0.pol", "dm0.wfs1", "dm1", "dm1.pol", "dm1.wfs0"]
    for i in range(len(cfg.dms)):
        lp = _loop(system, f"dm{i}")
        coeffs = _native(lp.modal_coefficients)
        assert coeffs.dtype == np.float64
        np.testing.assert_array_equal(coeffs, run.logs[f"dm{i}.residual"].coeffs)
        np.testing.assert_array_equal(_native(lp.commands), run.logs[f"dm{i}.commands"].coeffs)
        np.testing.assert_array_equal(_native(_loop(system, f"dm{i}.pol").modal_coefficients),
                                      run.logs[f"dm{i}.pol"].coeffs)
        np.testing.assert_array_equal(np.asarray(lp.time.timestamps), run.times)
        assert lp.modal_coefficients.unit == "rad" and lp.commands.unit == "rad"
        assert lp.framerate == 1.0 / cfg.loop.time_step
        assert lp.delay == cfg.loop.delay_frames == 0.5
        # integrator c_k = (1 - leak) c_{k-1} + g m_k  ->  num [[g]], den [[1, -(1 - leak)]]
        np.testing.assert_array_equal(_native(lp.time_filter_num), [[cfg.loop.gain]])
        np.testing.assert_array_equal(_native(lp.time_filter_den), [[1.0, -(1.0 - 0.01)]])
        assert lp.input_sensor.uid == f"wfs{i}" and lp.commanded_corrector.uid == f"dm{i}"
    for j, w in enumerate(system.wavefront_sensors):
        assert isinstance(w, aotpy.ShackHartmann) and w.uid == f"wfs{j}"
        meas = _native(w.measurements)
        assert meas.shape == (run.times.size, 2, w.n_valid_subapertures)
        assert w.measurements.unit == "rad/m"
        np.testing.assert_array_equal(meas.reshape(run.times.size, -1), run.measurements[j])
        np.testing.assert_array_equal(np.asarray(w.measurements.time.timestamps), run.times)
        assert isinstance(w.source, aotpy.NaturalGuideStar) and w.source.uid == "sun"


def test_geometry_atmosphere_and_config_are_described(run, cfg, model, system):
    geom = geometry_of(system)
    assert geom["sources"]["sun"]["extra"]["extended"] == "sun"
    for i, d in enumerate(cfg.dms):
        assert geom["correctors"][f"dm{i}"]["altitude"] == d.altitude
        assert system.wavefront_correctors[i].n_valid_actuators == d.n_modes
    for j, w in enumerate(cfg.wfss):
        assert geom["sensors"][f"wfs{j}"]["altitude"] == w.altitude
        assert geom["sensors"][f"wfs{j}"]["field_of_view"] == w.field_of_view
        mask = _native(system.wavefront_sensors[j].subaperture_mask)
        assert mask.shape == (w.n_subapertures, w.n_subapertures)
        valid = model.wfss[j].valid_subapertures
        np.testing.assert_array_equal(mask.ravel()[valid], np.arange(valid.size))
        assert np.all(np.delete(mask.ravel(), valid) == -1)
    tel = system.main_telescope
    assert tel.enclosing_diameter == cfg.telescope.diameter
    np.testing.assert_array_equal(_native(tel.pupil_mask) != 0, model.geometry.pupil_mask)
    (atm,) = system.atmosphere_params
    strength = np.array([lay.d_over_r0 for lay in cfg.layers]) ** (5.0 / 3.0)
    np.testing.assert_allclose(_native(atm.layers_relative_weight).ravel(),
                               strength / strength.sum(), rtol=1e-15)
    np.testing.assert_allclose(atm.r0[0], cfg.telescope.diameter / strength.sum() ** 0.6,
                               rtol=1e-15)
    assert atm.wavelength == cfg.r0_wavelength
    np.testing.assert_array_equal(_native(atm.layers_height).ravel(),
                                  [lay.altitude for lay in cfg.layers])
    np.testing.assert_array_equal(_native(atm.layers_wind_speed).ravel(),
                                  [lay.wind_speed for lay in cfg.layers])
    # AOT: 0 = North, increasing eastward, blowing from; +x = East, +y = North, written
    # in code here: the from-vector -(cos a, sin a) as a bearing atan2(east, north)
    a = np.radians([lay.wind_direction for lay in cfg.layers])
    bearing = np.degrees(np.arctan2(-np.cos(a), -np.sin(a))) % 360.0
    np.testing.assert_allclose(_native(atm.layers_wind_direction).ravel(), bearing,
                               rtol=0, atol=1e-12)
    np.testing.assert_array_equal(_native(atm.layers_l0).ravel(),  # inf: Kolmogorov, kept
                                  [lay.outer_scale for lay in cfg.layers])
    text = config_of(system)
    assert SimulationConfig.from_dict(tomllib.loads(text)) == run.config


def test_mode_images_and_reconstructor_blocks(run, cfg, model, system):
    meas = [_native(w.measurements).reshape(run.times.size, -1)
            for w in system.wavefront_sensors]
    for i, dm in enumerate(model.dms):
        lp = _loop(system, f"dm{i}")
        n = model.geometry.planes[dm.plane].n
        modes = _native(lp.modes).reshape(dm.n_modes, n * n)
        np.testing.assert_array_equal(modes[:, dm.pixels], dm.shapes.T)
        assert not np.delete(modes, dm.pixels, axis=1).any()
        np.testing.assert_array_equal(np.flatnonzero(_native(lp.commanded_corrector.pupil_mask)),
                                      dm.pixels)
        np.testing.assert_array_equal(_native(lp.modes_to_commands), np.eye(dm.n_modes))
        # the global reconstructor: own block + the other sensors' blocks rebuild the
        # loop's coefficients (numpy here; the loop summed them in another order)
        total = np.zeros((run.times.size, dm.n_modes))
        for k in range(len(model.wfss)):
            uid = f"dm{i}" if k == i else f"dm{i}.wfs{k}"
            block = _native(_loop(system, uid).measurements_to_modes)
            assert block.shape[1:] == (2, model.wfss[k].n_valid_subapertures)
            assert _loop(system, uid).input_sensor.uid == f"wfs{k}"
            total += meas[k] @ block.reshape(dm.n_modes, -1).T
        np.testing.assert_allclose(total, run.logs[f"dm{i}.residual"].coeffs, rtol=1e-9,
                                   atol=1e-12 * np.abs(total).max())


def test_modalinfo_load_gives_the_logs_bit_for_bit(run, cfg, model, exported):
    for i, dm in enumerate(model.dms):
        for uid, name in ((f"dm{i}", "residual"), (f"dm{i}.pol", "pol")):
            log = load(exported, loop=uid)
            ref = run.logs[f"dm{i}.{name}"]
            np.testing.assert_array_equal(log.coeffs, ref.coeffs)
            np.testing.assert_array_equal(log.timestamps, run.times)
            assert log.rate == ref.rate and log.units == "rad"
            assert list(log.modes) == list(ref.modes) == dm.modes
        meta = load(exported, loop=f"dm{i}").metadata
        assert meta["delay_frames"] == 0.5 and meta["corrector"]["altitude"] == cfg.dms[i].altitude
        assert meta["wfs"]["field_of_view"] == cfg.wfss[i].field_of_view


def test_modalinfo_load_keeps_the_phase_wavelength(run, cfg, model, exported, tmp_path):
    # audit 10, feedback, rows cl-aot-*: the logs are rad at r0_wavelength; read back they
    # had no wavelength, so `convert --units nm` needed one the user had to guess
    for i in range(len(model.dms)):
        for uid, name in ((f"dm{i}", "residual"), (f"dm{i}.pol", "pol")):
            log = load(exported, loop=uid)
            assert log.wavelength == run.logs[f"dm{i}.{name}"].wavelength == cfg.r0_wavelength
    nm = load(exported, loop="dm0").to_units("nm")
    np.testing.assert_allclose(  # OPD = phase x lambda / (2 pi), at 500 nm
        nm.coeffs, run.logs["dm0.residual"].coeffs * cfg.r0_wavelength * 1e9 / (2 * np.pi),
        rtol=1e-15)


@pytest.mark.parametrize("uid,modes", [("dm0", "Z2-Z36"), ("dm1", "Z2-Z21")])
def test_modalinfo_info_identifies_the_dm_modes_as_zernikes(exported, capsys, uid, modes):
    # dm1 (10 km) has a 4.97 m disc (39.8 px) on a 72 px plane grid: identification crops
    # to the disc's mask and still finds every Zernike, no sign or axis flip
    assert modalinfo_main(["info", str(exported), "--loop", uid]) == 0
    out = capsys.readouterr().out
    assert f"Zernike {modes} (Noll) in our convention, no sign or axis flip" in out


def test_the_correctors_name_their_noll_range(cfg, system):
    # a Zernike DM of n_modes controls Noll Z2 .. Z(n_modes + 1) (piston excluded), the
    # range modalinfo's identification finds in the exported mode images (test above)
    geom = geometry_of(system)
    for i, d in enumerate(cfg.dms):
        extra = geom["correctors"][f"dm{i}"]["extra"]
        assert extra["modes"] == f"Z2..Z{d.n_modes + 1} (Noll)"


def test_never_overwrites_unasked(run, model, exported):
    before = exported.read_bytes()
    with pytest.raises(FileExistsError, match="overwrite"):
        export_aot(run, exported, model=model)
    assert exported.read_bytes() == before
    export_aot(run, exported, model=model, overwrite=True)
    again = aotpy.AOSystem.read_from_file(exported)
    np.testing.assert_array_equal(_native(_loop(again, "dm1").modal_coefficients),
                                  run.logs["dm1.residual"].coeffs)


def test_model_of_another_config_is_refused(run, tmp_path):
    other = LoopModel(small(leak=0.02))
    with pytest.raises(ValueError, match="another config"):
        export_aot(run, tmp_path / "x.fits", model=other)
    assert not (tmp_path / "x.fits").exists()


def test_ideal_sensors_single_dm(tmp_path):
    base = small()
    c = base.replace(dms=(DMConfig(altitude=0.0, n_modes=9),),
                     wfss=(WFSConfig(altitude=0.0, field_of_view=base.wfss[0].field_of_view,
                                     kind="ideal", field_samples=1, dm=0),),
                     layers=base.layers[:1])
    r = simulate(c, 0.01, seed=1, progress=False)
    path = export_aot(r, tmp_path / "ideal.fits")
    system = aotpy.AOSystem.read_from_file(path)
    (w,) = system.wavefront_sensors
    assert isinstance(w, aotpy.Pyramid) and geometry_of(system)["sensors"]["wfs0"]["extra"][
        "kind"] == "ideal"
    np.testing.assert_array_equal(_native(w.measurements).reshape(r.times.size, -1),
                                  r.measurements[0])
    model = LoopModel(c)
    lp = _loop(system, "dm0")
    np.testing.assert_array_equal(_native(lp.measurements_to_modes).reshape(9, -1),
                                  model.wfss[0].reconstructor)
    np.testing.assert_array_equal(load(path, loop="dm0").coeffs, r.logs["dm0.residual"].coeffs)
    assert [lp.uid for lp in system.loops] == ["dm0", "dm0.pol"]


def test_command_line_export(run, tmp_path, capsys):
    h5 = tmp_path / "run.h5"
    run.save(h5)
    out = tmp_path / "run.fits"
    assert closedloop_main(["export", str(h5), str(out)]) == 0
    assert "AOT system of 30 frames" in capsys.readouterr().out
    np.testing.assert_array_equal(load(out, loop="dm0").coeffs, run.logs["dm0.residual"].coeffs)
    before = out.read_bytes()
    for argv, needle in [
        (["export", str(h5), str(out)], "--overwrite"),
        (["export", str(h5), str(tmp_path / "run.h5x")], "unsupported extension '.h5x'; use .fits"),
        (["export", str(tmp_path / "missing.h5"), str(tmp_path / "new.fits")], "does not exist"),
        (["export", str(h5), str(tmp_path / "nodir" / "a.fits")], "does not exist"),
    ]:
        assert closedloop_main(argv) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and needle in err and "Traceback" not in err
    assert out.read_bytes() == before
    assert not (tmp_path / "new.fits").exists()
    assert closedloop_main(["export", str(h5), str(out), "--overwrite"]) == 0


def test_strehl_ratio_wavelength_and_loop_numbers_read_back(run, cfg, system, exported):
    # the reported bug: aotpy 3.2.1 wrote strehl_wavelength under STREHL-R (read back as
    # the SR, 6.3e-07) and no STREHL-L (strehl_wavelength None)
    from astropy.io import fits

    sr = run.summary()["strehl_field_mean"]
    assert 1e-3 < sr < 1.0  # a Strehl ratio, not a wavelength in metres (6.3e-07)
    assert system.strehl_ratio == sr
    assert system.strehl_wavelength == cfg.wavelength
    header = fits.getheader(exported, 0)
    assert (header["STREHL-R"], header["STREHL-L"]) == (sr, cfg.wavelength)
    assert "STREHL-L" not in [m.key for m in system.metadata]  # an AOT keyword, not a card
    for i in range(len(cfg.dms)):
        lp = _loop(system, f"dm{i}")
        assert lp.framerate == 1.0 / cfg.loop.time_step
        assert lp.delay == cfg.loop.delay_frames
        assert lp.closed is True
        # c_k = (1 - leak) c_{k-1} + gain m_k: C(z) = gain / (1 - (1 - leak) z^-1)
        np.testing.assert_array_equal(_native(lp.time_filter_num).ravel(), [cfg.loop.gain])
        np.testing.assert_array_equal(_native(lp.time_filter_den).ravel(),
                                      [1.0, -(1.0 - cfg.loop.leak)])
        assert lp.commanded_corrector.uid == f"dm{i}"
        assert lp.commanded_corrector.n_valid_actuators == cfg.dms[i].n_modes
    assert [w.uid for w in system.wavefront_sensors] == [f"wfs{j}" for j in range(len(cfg.wfss))]
