"""AOT (Adaptive Optics Telemetry) files: detection, round trips, loop choice and bad input.

References: ``aotpy`` itself (systems are built and read back with ``aotpy.AOSystem``
directly, independently of our builder), exact round trips (bitwise equality), the
matrix product ``measurements_to_modes @ measurements`` computed here with numpy,
and the documented error contract of ``modalinfo.io`` (``LogFormatError`` naming the
file); the integrator time filter against the recursion ``u_k = (1 - leak) u_{k-1} +
g e_k`` written out here, and its round trip through ``integrator_from_filter``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

aotpy = pytest.importorskip("aotpy")

from modalinfo.bases import Pupil, ZernikeBasis  # noqa: E402
from modalinfo.io import LogFormatError, detect_format, load, save  # noqa: E402
from modalinfo.io.aot import aot_loops, read_aot_basis, read_aot_system, write_aot  # noqa: E402
from modalinfo.io.aot_system import (  # noqa: E402
    AtmosphereSpec,
    CorrectorSpec,
    LoopSpec,
    SensorSpec,
    SourceSpec,
    TelescopeSpec,
    build_system,
    config_of,
    geometry_of,
    integrator_filter,
    integrator_from_filter,
)
from modalinfo.telemetry import ModalLog  # noqa: E402


def _write_aotpy(system, path):
    """Write with aotpy alone (no modalinfo code), silencing its empty-table notes."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system.write_to_file(str(path))
    return path


def _multi_loop_system(rng):
    """Three control loops built with aotpy directly: float64, float32, reconstructed."""
    tel = aotpy.MainTelescope(uid="TEL", enclosing_diameter=8.0)
    ngs = aotpy.NaturalGuideStar(uid="NGS")
    lgs = aotpy.NaturalGuideStar(uid="NGS2")
    w1 = aotpy.ShackHartmann(uid="WFS-HO", source=ngs, n_valid_subapertures=6,
                             measurements=None)
    w2 = aotpy.Pyramid(uid="WFS-LO", source=lgs, n_valid_subapertures=3, n_sides=4)
    dm1 = aotpy.DeformableMirror(uid="DM-HO", telescope=tel, n_valid_actuators=40)
    dm2 = aotpy.TipTiltMirror(uid="TTM", telescope=tel)
    ts = 1.7e9 + np.arange(64) / 1000.0
    t_ho = aotpy.Time("HO time", timestamps=ts.tolist())
    c_ho = rng.standard_normal((64, 5))
    c_lo = rng.standard_normal((64, 2)).astype(np.float32)
    meas = rng.standard_normal((64, 2, 6))
    w1.measurements = aotpy.Image("HO slopes", meas, time=t_ho)
    m2m = rng.standard_normal((4, 2, 6))
    loops = [
        aotpy.ControlLoop(uid="HO", input_sensor=w1, commanded_corrector=dm1, time=t_ho,
                          framerate=1000.0, delay=1.3,
                          modal_coefficients=aotpy.Image("HO coeffs", c_ho, unit="rad",
                                                         time=t_ho)),
        aotpy.ControlLoop(uid="LO", input_sensor=w2, commanded_corrector=dm2,
                          framerate=250.0, closed=False,
                          modal_coefficients=aotpy.Image("LO coeffs", c_lo, unit="nm")),
        aotpy.ControlLoop(uid="REC", input_sensor=w1, commanded_corrector=dm1, time=t_ho,
                          framerate=1000.0,
                          measurements_to_modes=aotpy.Image("S2M", m2m)),
    ]
    system = aotpy.AOSystem(ao_mode="MCAO", name="TEST", main_telescope=tel, sources=[ngs, lgs],
                            wavefront_sensors=[w1, w2], wavefront_correctors=[dm1, dm2],
                            loops=loops)
    return system, {"HO": c_ho, "LO": c_lo, "ts": ts, "meas": meas, "m2m": m2m}


@pytest.fixture(scope="module")
def multi(tmp_path_factory):
    rng = np.random.default_rng(7)
    system, arrays = _multi_loop_system(rng)
    path = _write_aotpy(system, tmp_path_factory.mktemp("aot") / "multi.fits")
    return path, arrays


# ----------------------------------------------------------------------------- detection
def test_detects_aot_and_not_our_fits(multi, tmp_path):
    path, _ = multi
    assert detect_format(path) == "aot"
    ours = save(ModalLog(np.zeros((3, 2)), rate=10.0), tmp_path / "ours.fits")
    assert detect_format(ours) == "fits"
    from astropy.io import fits

    fits.PrimaryHDU(np.ones((4, 3))).writeto(tmp_path / "plain.fits")
    assert detect_format(tmp_path / "plain.fits") == "fits"


# ----------------------------------------------------------------------------- written by aotpy
def test_aotpy_multi_loop_to_modalinfo_bitwise(multi):
    path, arrays = multi
    assert aot_loops(path) == ["HO", "LO", "REC"]
    ho = load(path, loop="HO")
    assert ho.coeffs.dtype == np.float64
    assert np.array_equal(ho.coeffs.view(np.uint8), arrays["HO"].view(np.uint8))
    assert np.array_equal(ho.timestamps.view(np.uint8), arrays["ts"].view(np.uint8))
    assert ho.rate == 1000.0 and ho.units == "rad"
    meta = ho.metadata
    assert meta["loop_uid"] == "HO" and meta["loop"] == "closed"
    assert meta["diameter"] == 8.0 and meta["delay_frames"] == pytest.approx(1.3)
    assert meta["wfs"]["type"] == "ShackHartmann" and meta["wfs"]["n_valid_subapertures"] == 6
    assert meta["corrector"] == {"uid": "DM-HO", "type": "DeformableMirror",
                                 "n_valid_actuators": 40}
    lo = load(path, loop="LO")
    assert lo.coeffs.dtype == np.float32  # AOT keeps the image dtype
    assert np.array_equal(lo.coeffs.view(np.uint8), arrays["LO"].view(np.uint8))
    assert lo.timestamps is None and lo.rate == 250.0 and lo.units == "nm"
    assert lo.metadata["loop"] == "open" and lo.metadata["wfs"]["type"] == "Pyramid"


def test_reconstructed_coefficients_are_the_matrix_product(multi):
    path, arrays = multi
    rec = load(path, loop="REC")
    expected = arrays["meas"].reshape(64, -1) @ arrays["m2m"].reshape(4, -1).T
    assert np.array_equal(rec.coeffs, expected)
    assert rec.metadata["coefficients"].startswith("reconstructed")
    assert np.array_equal(rec.timestamps, arrays["ts"])


def test_system_read_by_aotpy_and_modalinfo_agree(multi):
    path, _ = multi
    system = read_aot_system(path)
    ho = next(lp for lp in system.loops if lp.uid == "HO")
    assert np.array_equal(load(path, loop="HO").coeffs, np.asarray(ho.modal_coefficients.data))


# ----------------------------------------------------------------------------- ModalLog round trip
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("timed", [False, True])
def test_modallog_aot_modallog_bitwise(tmp_path, assert_same_log, dtype, timed):
    rng = np.random.default_rng(1)
    kwargs = ({"timestamps": np.cumsum(rng.uniform(0.9e-3, 1.1e-3, 120))} if timed
              else {"rate": 977.5, "start_time": 0.25})
    log = ModalLog(rng.standard_normal((120, 6)).astype(dtype), modes=[2, 3, 4, 5, 6, 7],
                   units="nm", wavelength=6.3e-7,
                   metadata={"telescope": "LOST", "loop": "closed", "values": [1, 2.5, "é"]},
                   **kwargs)
    path = save(log, tmp_path / "log.fits", fmt="aot")
    assert detect_format(path) == "aot"
    back = load(path)
    assert_same_log(log, back)
    # what aotpy itself reads is the same array
    lp = read_aot_system(path).loops[0]
    assert np.array_equal(np.asarray(lp.modal_coefficients.data), log.coeffs)
    if timed:
        assert lp.framerate is None or np.isnan(lp.framerate)  # AOT null
    else:
        assert lp.framerate == 977.5


def test_write_with_basis_gives_the_basis_back(tmp_path):
    basis = ZernikeBasis(Pupil(24, diameter=4.0), modes=range(2, 9))
    log = ModalLog(np.random.default_rng(2).standard_normal((30, 7)), rate=100.0,
                   modes=list(range(2, 9)))
    path = write_aot(log, tmp_path / "b.fits", basis=basis)
    back, ident = read_aot_basis(path)
    assert back.pupil == basis.pupil
    assert np.array_equal(back.matrix, basis.matrix)
    assert back.labels == [f"Z{j}" for j in range(2, 9)]
    assert ident.is_standard and list(ident.noll) == list(range(2, 9))
    with pytest.raises(ValueError, match="7 modes but the log has 3"):
        write_aot(log.select(modes=[2, 3, 4]), tmp_path / "c.fits", basis=basis)


def test_writer_never_overwrites_unasked(tmp_path):
    log = ModalLog(np.ones((4, 2)), rate=10.0)
    path = save(log, tmp_path / "x.fits", fmt="aot")
    with pytest.raises(FileExistsError, match="overwrite"):
        save(log, path, fmt="aot")
    save(log.with_metadata(v=2), path, fmt="aot", overwrite=True)
    assert load(path).metadata == {"v": 2}
    assert [p.name for p in tmp_path.iterdir()] == ["x.fits"]  # no temporary left


# ----------------------------------------------------------------------------- builder
def test_build_system_complete_export_round_trip(tmp_path):
    """A closedloop-like export: 2 DMs at altitudes, 2 WFSs, atmosphere, integrator."""
    rng = np.random.default_rng(3)
    t = np.arange(50) * 1e-3
    basis = ZernikeBasis(Pupil(16), modes=range(2, 6))
    modes = np.nan_to_num(basis.pupil.to_image(basis.matrix.T))
    num, den = integrator_filter(0.4, leak=0.01)  # den [[1, -0.99]]
    loops, sensors, correctors = [], [], []
    coeffs, meas, cmds, m2m = {}, {}, {}, {}
    for k, alt in enumerate((0.0, 8000.0)):
        coeffs[k] = rng.standard_normal((50, 4))
        meas[k] = rng.standard_normal((50, 2, 12)).astype(np.float32)
        cmds[k] = rng.standard_normal((50, 30))
        m2m[k] = rng.standard_normal((4, 2, 12))
        sensors.append(SensorSpec(f"WFS{k}", "sun", 12, measurements=meas[k],
                                  field_of_view=(60.0, 20.0)[k], altitude=alt))
        correctors.append(CorrectorSpec(f"DM{k}", 30, altitude=alt))
        loops.append(LoopSpec(f"L{k}", f"WFS{k}", f"DM{k}", modal_coefficients=coeffs[k],
                              units="rad", timestamps=t, framerate=1000.0, delay=1.5,
                              modes=modes, measurements_to_modes=m2m[k], commands=cmds[k],
                              time_filter_num=num, time_filter_den=den))
    system = build_system(
        loops, sensors=sensors, correctors=correctors,
        sources=[SourceSpec("sun", extra={"extended": "sun"})],
        telescope=TelescopeSpec(diameter=4.0),
        atmosphere=[AtmosphereSpec(r0=0.15, wavelength=5e-7, heights=[0.0, 8000.0],
                                   weights=[0.9, 0.1], wind_speeds=[7.0, 70.0],
                                   wind_directions=[0.0, 90.0])],
        name="closedloop", config="[seed]\nvalue = 0\n")
    path = _write_aotpy(system, tmp_path / "run.fits")
    read = read_aot_system(path)
    assert read.ao_mode == "MCAO"
    assert config_of(read) == "[seed]\nvalue = 0\n"
    assert geometry_of(read)["correctors"] == {"DM0": {"altitude": 0.0},
                                               "DM1": {"altitude": 8000.0}}
    atm = read.atmosphere_params[0]
    assert np.array_equal(atm.layers_wind_speed.data, [[7.0, 70.0]])
    for k in (0, 1):
        lp = read.loops[k]  # what aotpy reads: the same bits, dtype kept
        for got, want in ((lp.input_sensor.measurements.data, meas[k]),
                          (lp.commands.data, cmds[k]), (lp.measurements_to_modes.data, m2m[k]),
                          (lp.modes.data, modes)):
            got = np.asarray(got)
            assert got.dtype.newbyteorder("=") == want.dtype and np.array_equal(got, want)
        log = load(path, loop=f"L{k}")
        assert np.array_equal(log.coeffs, coeffs[k]) and np.array_equal(log.timestamps, t)
        assert log.modes == [2, 3, 4, 5]  # identified from the mode images
        assert log.metadata["corrector"]["altitude"] == (0.0, 8000.0)[k]
        assert log.metadata["wfs"]["field_of_view"] == (60.0, 20.0)[k]
        assert log.metadata["time_filter"] == {"num": [[0.4]], "den": [[1.0, -0.99]]}


@pytest.mark.parametrize("leak", [0.0, 0.01, 0.3, 0.5, 0.999])
def test_integrator_filter_is_the_simulator_integrator(leak):
    from scipy.signal import lfilter

    gain = np.array([0.4, 0.25])
    num, den = integrator_filter(gain, leak)
    e = np.random.default_rng(0).standard_normal((40, 2))
    u = np.zeros(2)
    expected = []
    for e_k in e:  # the simulator's controller: leak 0 is a pure integrator
        u = (1.0 - leak) * u + gain * e_k
        expected.append(u)
    got = np.column_stack([lfilter(num[i], den[i], e[:, i]) for i in range(2)])
    np.testing.assert_allclose(got, np.array(expected), rtol=1e-12, atol=1e-13)
    g_back, leak_back = integrator_from_filter(num, den)
    assert np.array_equal(g_back, gain)
    # 1 - leak rounds once (at most 2^-53 absolute for leak in [0, 1)); 1 + den is exact
    np.testing.assert_allclose(leak_back, leak, rtol=0, atol=2.0**-53)


def test_integrator_from_filter_rejects_other_filters():
    with pytest.raises(ValueError, match="num \\(m, 1\\) and den \\(m, 2\\)"):
        integrator_from_filter([[0.4, 0.1]], [[1.0, -0.9]])
    with pytest.raises(ValueError, match="`den` must start with 1"):
        integrator_from_filter([[0.4]], [[2.0, -0.9]])


def test_build_system_rejects_unknown_references():
    with pytest.raises(ValueError, match="names sensor 'nope'"):
        build_system([LoopSpec("L", "nope", "DM")], sensors=[SensorSpec("W", "source")],
                     correctors=[CorrectorSpec("DM")])
    with pytest.raises(ValueError, match="share the uid 'W'"):
        build_system([LoopSpec("L", "W", "DM")],
                     sensors=[SensorSpec("W", "source"), SensorSpec("W", "source")],
                     correctors=[CorrectorSpec("DM")])


# ----------------------------------------------------------------------------- bad input
def test_several_loops_need_a_choice_listing_the_uids(multi):
    path, _ = multi
    with pytest.raises(LogFormatError, match=r"3 control loops \('HO', 'LO', 'REC'\)") as err:
        load(path)
    assert str(path) in str(err.value)
    with pytest.raises(LogFormatError, match=r"no control loop 'X'; its loops: 'HO', 'LO'"):
        load(path, loop="X")


def test_loop_must_be_a_str(multi):
    with pytest.raises(TypeError, match="`loop` must be a str"):
        load(multi[0], loop=3)


def test_loop_hint_on_another_format_is_refused(tmp_path):
    path = save(ModalLog(np.ones((3, 2)), rate=1.0), tmp_path / "a.npz")
    with pytest.raises(ValueError, match="`loop` selects a control loop of an AOT file"):
        load(path, loop="HO")


def test_file_without_loop(tmp_path):
    tel = aotpy.MainTelescope(uid="TEL")
    path = _write_aotpy(aotpy.AOSystem(ao_mode="SCAO", main_telescope=tel),
                        tmp_path / "noloop.fits")
    with pytest.raises(LogFormatError, match="has no control loop") as err:
        load(path)
    assert "noloop.fits" in str(err.value)


def test_modes_count_differs_from_columns(tmp_path):
    tel = aotpy.MainTelescope(uid="TEL")
    ngs = aotpy.NaturalGuideStar(uid="NGS")
    wfs = aotpy.ShackHartmann(uid="W", source=ngs, n_valid_subapertures=1)
    dm = aotpy.DeformableMirror(uid="DM", telescope=tel, n_valid_actuators=1)
    basis = ZernikeBasis(Pupil(16), modes=range(2, 5))
    modes = np.nan_to_num(basis.pupil.to_image(basis.matrix.T))
    loop = aotpy.ControlLoop(uid="L", input_sensor=wfs, commanded_corrector=dm,
                             modes=aotpy.Image("MODES", modes),
                             modal_coefficients=aotpy.Image("C", np.zeros((10, 5))))
    path = _write_aotpy(aotpy.AOSystem(ao_mode="SCAO", main_telescope=tel, sources=[ngs],
                                       wavefront_sensors=[wfs], wavefront_correctors=[dm],
                                       loops=[loop]), tmp_path / "bad_modes.fits")
    with pytest.raises(LogFormatError, match="has 3 modes but its coefficients have 5 columns"):
        load(path)


@pytest.mark.parametrize("keep", [0.3, 0.6, 0.9, 0.995])
def test_truncated_file(multi, tmp_path, keep):
    path, _ = multi
    data = path.read_bytes()
    cut = tmp_path / "cut.fits"
    cut.write_bytes(data[: int(len(data) * keep)])
    with pytest.raises(LogFormatError) as err:
        load(cut, loop="HO")
    assert "cut.fits" in str(err.value)


def test_altered_data_fails_its_checksum(tmp_path):
    log = ModalLog(np.arange(40.0).reshape(20, 2), rate=10.0)
    path = save(log, tmp_path / "x.fits", fmt="aot")
    raw = bytearray(path.read_bytes())
    # flip one byte inside the coefficient image (the last HDU, data at the end)
    raw[-2880 + 100] ^= 0xFF
    path.write_bytes(bytes(raw))
    with pytest.raises(LogFormatError, match="x.fits"):
        load(path)


def test_aotpy_verification_remarks_are_kept(multi, tmp_path):
    """A WARNING-level defect (data in the primary HDU) is read, and said in metadata."""
    from aotpy.io.fits import AOTFITSWriter

    hdul = AOTFITSWriter(read_aot_system(multi[0])).get_hdulist()
    hdul[0].data = np.ones(2)
    hdul.writeto(tmp_path / "odd.fits")
    log = load(tmp_path / "odd.fits", loop="HO")
    assert np.array_equal(log.coeffs, multi[1]["HO"])
    assert any("Primary HDU should not contain data" in w
               for w in log.metadata["aot_warnings"])
