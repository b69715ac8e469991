"""Command-line use of AOT files: ``--loop`` on every reading command, the mode table, bad input.

References: the dispatcher contract (one line on stderr, exit 2, no traceback, also in
a real subprocess); the identification and orderings are compared with the library
functions called directly on the same file (``modalinfo.io.aot.read_aot_basis``,
``modalinfo.ordering.order_modes``); the NAOMI control modes shipped by ``aotpy``
(Zernike 2-15, aotpy's NAOMI translator) give the expected table.
"""

from __future__ import annotations

import importlib.resources
import subprocess
import sys
import warnings

import numpy as np
import pytest

aotpy = pytest.importorskip("aotpy")

from modalinfo.cli import main  # noqa: E402
from modalinfo.io import load  # noqa: E402
from modalinfo.io.aot import read_aot_basis  # noqa: E402


def _write(system, path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system.write_to_file(str(path))
    return path


@pytest.fixture(scope="module")
def naomi_file(tmp_path_factory):
    """An AOT system with NAOMI's control modes and two loops (one without modes)."""
    from astropy.io import fits

    res = importlib.resources.files("aotpy.data.NAOMI") / "zernike_control_modes.fits"
    with importlib.resources.as_file(res) as p:
        modes = fits.getdata(p)
    rng = np.random.default_rng(5)
    tel = aotpy.MainTelescope(uid="AT1", enclosing_diameter=1.82)
    ngs = aotpy.NaturalGuideStar(uid="NGS")
    wfs = aotpy.ShackHartmann(uid="WFS", source=ngs, n_valid_subapertures=12)
    dm = aotpy.DeformableMirror(uid="DM", telescope=tel, n_valid_actuators=241)
    t = aotpy.Time("Loop Time", timestamps=(1.6e9 + np.arange(400) / 500.0).tolist())
    # AR(1) coefficients with decreasing variance, so orderings are not arbitrary
    x = np.zeros((400, 14))
    scale = 1.0 / np.arange(1, 15)
    for k in range(1, 400):
        x[k] = 0.9 * x[k - 1] + scale * rng.standard_normal(14)
    main_loop = aotpy.ControlLoop(
        uid="Main Loop", input_sensor=wfs, commanded_corrector=dm, time=t, framerate=500.0,
        delay=1.8, modes=aotpy.Image("CONTROL MODES", modes),
        modal_coefficients=aotpy.Image("Modal Coefficients", x, time=t))
    other = aotpy.ControlLoop(
        uid="Other", input_sensor=wfs, commanded_corrector=dm, framerate=500.0,
        modal_coefficients=aotpy.Image("Other coefficients", rng.standard_normal((50, 3))))
    system = aotpy.AOSystem(ao_mode="SCAO", name="NAOMI", main_telescope=tel, sources=[ngs],
                            wavefront_sensors=[wfs], wavefront_correctors=[dm],
                            loops=[main_loop, other])
    return _write(system, tmp_path_factory.mktemp("cli_aot") / "naomi.fits")


def test_info_shows_the_identification_table(naomi_file, capsys):
    assert main(["info", str(naomi_file), "--loop", "Main Loop", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "400 frames x 14 modes" in out and "Z2 .. Z15 (noll)" in out
    assert "500 Hz" in out and "delay_frames: 1.8" in out and "diameter: 1.82" in out
    lines = out.splitlines()
    start = next(i for i, s in enumerate(lines) if s.split()[:2] == ["mode", "noll"])
    rows = [s.split() for s in lines[start + 1:start + 15]]
    assert [int(r[1]) for r in rows] == list(range(2, 16))
    assert [r[-1] for r in rows] == [f"+Z{j}" for j in range(2, 16)]
    assert all(float(r[3]) > 0.999 for r in rows)
    assert "Zernike Z2-Z15 (Noll) in our convention, no sign or axis flip" in out


def test_other_loop_and_default_labels(naomi_file, capsys):
    assert main(["info", str(naomi_file), "--loop", "Other", "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "50 frames x 3 modes" in out and "modes_note" in out
    assert "against our Zernikes" not in out


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["info", "{f}", "--loop", "X"], "no control loop 'X'; its loops: 'Main Loop', 'Other'"),
        (["info", "{f}"], "2 control loops ('Main Loop', 'Other'); choose one"),
        (["reorder", "{f}", "--loop", "X"], "no control loop 'X'"),
        (["fitting-error", "{f}", "--loop", "Nope"], "no control loop 'Nope'"),
        (["forecast", "{f}", "--loop", "X"], "no control loop 'X'"),
        (["convert", "{f}", "{out}", "--loop", "X"], "no control loop 'X'"),
        (["reorder", "{f}", "--loop", "Other", "--basis", "file"],
         "loop 'Other' has no mode images"),
    ],
)
def test_bad_loop_is_one_line_exit_2(naomi_file, tmp_path, capsys, argv, needle):
    argv = [a.format(f=naomi_file, out=tmp_path / "o.npz") for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err and "naomi.fits" in err


def test_bad_files_in_a_subprocess(naomi_file, tmp_path):
    cut = tmp_path / "cut.fits"
    cut.write_bytes(naomi_file.read_bytes()[: naomi_file.stat().st_size // 2])
    noloop = _write(aotpy.AOSystem(ao_mode="SCAO", main_telescope=aotpy.MainTelescope(uid="T")),
                    tmp_path / "noloop.fits")
    for path, needle in ((cut, "cut.fits"), (noloop, "has no control loop")):
        proc = subprocess.run([sys.executable, "-m", "modalinfo", "info", str(path), "--loop",
                               "Main Loop"], capture_output=True, text=True, timeout=120)
        assert proc.returncode == 2, proc.stderr
        assert proc.stderr.count("\n") == 1 and needle in proc.stderr
        assert "Traceback" not in proc.stderr


def test_loop_on_a_non_aot_file(tmp_path, capsys):
    path = tmp_path / "plain.csv"
    np.savetxt(path, np.ones((10, 2)), delimiter=",")
    assert main(["info", str(path), "--loop", "L"]) == 2
    assert "selects a control loop of an AOT file" in capsys.readouterr().err


def test_reorder_in_the_file_basis_equals_the_library(naomi_file, capsys):
    from modalinfo.ordering import order_modes

    argv = ["reorder", str(naomi_file), "--loop", "Main Loop", "--basis", "file",
            "--method", "variance", "--resamples", "0"]  # --budget: MI only (round 17)
    assert main(argv) == 0
    out = capsys.readouterr().out
    basis, _ = read_aot_basis(naomi_file, loop="Main Loop")
    log = load(naomi_file, loop="Main Loop")
    direct = order_modes(log, basis, "variance", sample_budget=20000)
    rows = [line.split() for line in out.splitlines()]
    printed = [r[1] for r in rows if r and r[0].lstrip("~").isdigit()][:14]
    assert printed == [basis.labels[k] for k in direct.order]
    assert printed[0] == "Z2"  # largest variance by construction


def test_fitting_error_with_file_and_zernike_bases(naomi_file, capsys):
    argv = ["fitting-error", str(naomi_file), "--loop", "Main Loop", "--orderings",
            "file:standard,zernike:standard", "--pupil-pixels", "256"]  # no MI: no --budget
    assert main(argv) == 0
    out = capsys.readouterr().out
    rows = {line.split()[0]: [float(v) for v in line.split()[1:]]
            for line in out.splitlines() if line.startswith(("file:", "zernike:"))}
    # the file's modes are our Zernikes on the same 256-px pupil (to its pixelation)
    assert np.allclose(rows["file:standard"], rows["zernike:standard"], rtol=0.02)


def test_convert_to_aot_and_back(naomi_file, tmp_path, capsys):
    out = tmp_path / "copy.fits"
    assert main(["convert", str(naomi_file), str(out), "--loop", "Main Loop",
                 "--to-fmt", "aot", "--quiet"]) == 0
    a, b = load(naomi_file, loop="Main Loop"), load(out)
    assert np.array_equal(a.coeffs, b.coeffs) and np.array_equal(a.timestamps, b.timestamps)
    # the copy adds only the record of its conversion (round 18 PART b, P06)
    assert b.metadata["provenance"][-1]["command"][:2] == ["modalinfo", "convert"]
    kept = {k: v for k, v in b.metadata.items() if k != "provenance"}
    assert a.metadata == kept and a.modes == b.modes


def test_modes_count_mismatch_is_one_line(tmp_path, capsys):
    from modalinfo.io.aot import write_system
    from modalinfo.io.aot_system import CorrectorSpec, LoopSpec, SensorSpec, build_system

    system = build_system([LoopSpec("L", "W", "DM", modal_coefficients=np.zeros((8, 4)),
                                    modes=np.ones((3, 16, 16)))],
                          sensors=[SensorSpec("W", "source")], correctors=[CorrectorSpec("DM")])
    path = write_system(system, tmp_path / "mismatch.fits")
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "mismatch.fits" in err
    assert "has 3 modes but its coefficients have 4 columns" in err
