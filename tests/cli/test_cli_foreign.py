"""The command line on logs written by other software: no silent guesses.

References: files written with ``numpy.save``/``savez``, ``astropy.io.fits``, ``h5py``
and plain text; expected numbers from NumPy on the written arrays (per-mode mean and
standard deviation), the unit definitions (phase [rad] = 2 pi OPD / lambda), gaps
placed by construction; the dispatcher contract (exit 2, exactly one line on stderr
naming the file or flag, input files unchanged, no output written on refusal).
"""

from __future__ import annotations

import argparse

import h5py
import numpy as np
import pytest
from astropy.io import fits

from modalinfo.cli import build_parser, main

rng = np.random.default_rng(11)
X = np.cumsum(rng.standard_normal((1200, 5)), axis=0) * 0.01  # 1200 frames x 5 modes
HINT_FLAGS = ("--fmt", "--rate", "--in-units", "--in-modes", "--in-convention",
              "--wavelength", "--nonfinite", "--transpose", "--no-transpose", "--dataset")
LOG_COMMANDS = ("info", "reorder", "fitting-error", "forecast", "convert")


def _table(out: str) -> dict[str, list[float]]:
    lines = out.splitlines()
    start = next(i for i, line in enumerate(lines) if line.split()[:1] == ["mode"])
    return {ln.split()[0]: [float(v) for v in ln.split()[1:]] for ln in lines[start + 1:]}


def _one_line_error(capsys, *needles):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, err
    return err


def _options(command: str) -> set[str]:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {opt for action in sub.choices[command]._actions for opt in action.option_strings}


@pytest.mark.parametrize("command", LOG_COMMANDS)
def test_every_log_command_takes_the_same_hints(command):
    opts = _options(command)
    missing = [f for f in HINT_FLAGS if f not in opts and not (
        command == "convert" and f == "--wavelength")]
    assert not missing
    if command == "convert":
        assert {"--units", "--convention", "--wavelength"} <= opts  # output + phase wavelength
    # --units/--convention mean OUTPUT only in convert; elsewhere old spellings are aliases
    assert "--convention" not in opts or command == "convert"


@pytest.mark.parametrize("command", ["info", "reorder", "fitting-error", "forecast"])
@pytest.mark.parametrize("kind", ["npy", "fits", "h5"])
def test_transposed_log_is_refused_then_read_with_transpose(tmp_path, capsys, command, kind):
    stored = np.ascontiguousarray(np.tile(X, (1, 6))[:, :27].T)  # 27 modes x 1200 frames
    path = tmp_path / f"t.{kind}"
    if kind == "npy":
        np.save(path, stored)
    elif kind == "fits":
        fits.PrimaryHDU(stored).writeto(path)
    else:
        with h5py.File(path, "w") as f:
            f["data"] = stored
    before = path.read_bytes()
    extra = {"info": [], "reorder": ["--method", "variance", "--pupil-pixels", "16"],
             "fitting-error": ["--orderings", "zernike:standard", "--pupil-pixels", "16"],
             "forecast": ["--predictors", "linear", "--horizon", "1", "--rate", "1000"]}
    assert main([command, str(path), *extra[command]]) == 2
    _one_line_error(capsys, "t." + kind, "27 x 1200", "--transpose")
    assert path.read_bytes() == before
    if command == "info":
        assert main(["info", str(path), "--transpose", "--quiet"]) == 0
        out = capsys.readouterr().out
        assert "1200 frames x 27 modes" in out
        table = _table(out)
        np.testing.assert_allclose(table["Z2"][0], stored[0].mean(), rtol=1e-4, atol=1e-9)
        np.testing.assert_allclose(table["Z28"][2], stored[26].std(), rtol=1e-4)


def test_info_marks_assumed_values(tmp_path, capsys):
    np.save(tmp_path / "a.npy", X)
    assert main(["info", str(tmp_path / "a.npy")]) == 0
    out = capsys.readouterr().out
    assert "Z2, Z3, Z4, Z5, Z6 (noll) (assumed)" in out
    assert "units       rad (assumed)" in out
    assert main(["info", str(tmp_path / "a.npy"), "--in-units", "nm", "--in-modes", "4-8",
                 "--in-convention", "noll"]) == 0
    out = capsys.readouterr().out
    assert "(assumed)" not in out and ", assumed" not in out
    assert "units       nm" in out and "Z4, Z5, Z6, Z7, Z8 (noll)" in out


def test_analysis_commands_note_assumed_values(tmp_path, capsys):
    np.save(tmp_path / "a.npy", X)
    assert main(["fitting-error", str(tmp_path / "a.npy"), "--orderings",
                 "zernike:standard", "--pupil-pixels", "16"]) == 0
    err = capsys.readouterr().err
    # one line for the assumed values (the quality pass adds its own: X is a random walk,
    # too correlated to assess)
    assert sum("does not record" in line for line in err.splitlines()) == 1
    assert "note: 'a.npy' does not record its units, modes: assumed units rad" in err
    assert "--in-units" in err


def test_old_spellings_keep_one_meaning(tmp_path, capsys):
    np.save(tmp_path / "a.npy", X)
    # info --modes keeps its meaning (the column hint) as a deprecated alias
    assert main(["info", str(tmp_path / "a.npy"), "--modes", "4-8", "--in-units", "nm"]) == 0
    cap = capsys.readouterr()
    assert "Z4, Z5, Z6, Z7, Z8" in cap.out and "units       nm" in cap.out
    assert "--modes is deprecated; use --in-modes" in cap.err
    # --units means output units (convert) only: the old input/other spellings are refused
    for argv, needle in ((["info", "--units", "nm"], "--units: renamed --in-units"),
                         (["fitting-error", "--units", "rad2"], "renamed --error-units")):
        with pytest.raises(SystemExit) as exc:  # a usage error, as argparse reports them
            main([argv[0], str(tmp_path / "a.npy"), *argv[1:]])
        assert exc.value.code == 2
        _one_line_error(capsys, needle)
    assert main(["fitting-error", str(tmp_path / "a.npy"), "--orderings", "zernike:standard",
                 "--pupil-pixels", "16", "--error-units", "rad2", "--in-units", "rad"]) == 0
    assert "rad2" in capsys.readouterr().out


def test_convert_never_assumes_input_units(tmp_path, capsys):
    np.save(tmp_path / "a.npy", X)
    before = (tmp_path / "a.npy").read_bytes()
    out = tmp_path / "o.npz"
    assert main(["convert", str(tmp_path / "a.npy"), str(out), "--units", "nm",
                 "--wavelength", "5e-7"]) == 2
    _one_line_error(capsys, "--units nm", "a.npy", "--in-units")
    assert not out.exists() and (tmp_path / "a.npy").read_bytes() == before
    assert main(["convert", str(tmp_path / "a.npy"), str(out), "--units", "nm",
                 "--wavelength", "5e-7", "--in-units", "rad", "--quiet"]) == 0
    from modalinfo.io import load

    got = load(out)
    np.testing.assert_allclose(got.coeffs, X * 500.0 / (2 * np.pi), rtol=1e-12)
    assert got.units == "nm"


def test_wavelength_lets_analyses_read_nm_logs(tmp_path, capsys):
    lam = 6e-7
    np.save(tmp_path / "rad.npy", X)
    np.save(tmp_path / "nm.npy", X * lam * 1e9 / (2 * np.pi))
    args = ["--orderings", "zernike:standard", "--pupil-pixels", "16", "--error-units", "rad2"]
    assert main(["fitting-error", str(tmp_path / "nm.npy"), "--in-units", "nm", *args]) == 2
    capsys.readouterr()
    assert main(["fitting-error", str(tmp_path / "nm.npy"), "--in-units", "nm",
                 "--wavelength", str(lam), *args]) == 0
    nm_out = capsys.readouterr().out
    assert main(["fitting-error", str(tmp_path / "rad.npy"), "--in-units", "rad", *args]) == 0
    rad_out = capsys.readouterr().out

    def total(text):
        line = next(ln for ln in text.splitlines() if ln.startswith("total variance"))
        return float(line.split("=")[1].split()[0])

    assert total(nm_out) == pytest.approx(total(rad_out), rel=1e-3)


def test_csv_header_names_and_time_column_last(tmp_path, capsys):
    t_ms = np.arange(1200) * 0.5  # 2 kHz in ms, written as the last column
    names = ",".join(f"mode_{j}" for j in range(2, 7)) + ",time_ms"
    rows = [",".join(repr(float(v)) for v in (*X[k], t_ms[k])) for k in range(1200)]
    (tmp_path / "h.csv").write_text(names + "\n" + "\n".join(rows) + "\n")
    assert main(["info", str(tmp_path / "h.csv")]) == 0
    out = capsys.readouterr().out
    assert "1200 frames x 5 modes" in out and "2000 Hz median" in out
    assert "Z2, Z3, Z4, Z5, Z6 (noll, assumed)" in out  # 'mode_' names no convention
    np.testing.assert_allclose(_table(out)["Z4"][0], X[:, 2].mean(), rtol=1e-4)
    assert main(["info", str(tmp_path / "h.csv"), "--in-modes", "KL1,KL2,KL3,KL4,KL5"]) == 0
    out = capsys.readouterr().out
    assert "KL1, KL2, KL3, KL4, KL5 (labels)" in out and "relabelled" in out


@pytest.fixture
def gappy(tmp_path):
    t = np.arange(1200) / 2000.0
    t[600:] += 0.1  # one 0.1 s gap after frame 599
    names = "time," + ",".join(f"Z{j}" for j in range(2, 7))
    rows = [",".join(repr(float(v)) for v in (t[k], *X[k])) for k in range(1200)]
    path = tmp_path / "gap.csv"
    path.write_text(names + "\n" + "\n".join(rows) + "\n")
    return path, t


def test_info_reports_median_rate_jitter_and_gaps(gappy, capsys):
    path, t = gappy
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    mean_rate = 1199 / (t[-1] - t[0])
    assert f"2000 Hz median (mean {mean_rate:.6g} Hz)" in out
    assert "1 gap(s)" in out and "after frame 599" in out and "0.1005 s" in out
    assert "longest contiguous segment frames 0..599" in out


def test_analyses_refuse_gaps_unless_split(gappy, capsys, tmp_path):
    path, _ = gappy
    before = path.read_bytes()
    outdir = tmp_path / "res"
    assert main(["forecast", str(path), "--predictors", "linear", "--horizon", "1",
                 "--out", str(outdir)]) == 2
    _one_line_error(capsys, "gap.csv", "after frame 599", "--split-gaps")
    assert not outdir.exists() and path.read_bytes() == before
    assert main(["reorder", str(path), "--pupil-pixels", "16", "--budget", "3000",
                 "--resamples", "3"]) == 2
    _one_line_error(capsys, "gap.csv", "--split-gaps")
    assert main(["forecast", str(path), "--predictors", "linear", "--horizon", "1",
                 "--split-gaps"]) == 0
    cap = capsys.readouterr()
    assert "600 frames x 5 modes" in cap.out
    assert "--split-gaps: analysed frames 0..599 (600 of 1200)" in cap.err
    # the fitting error does not depend on the frame spacing: no refusal
    assert main(["fitting-error", str(path), "--orderings", "zernike:standard",
                 "--pupil-pixels", "16"]) == 0


def test_hdf5_dataset_and_time_in_ms(tmp_path, capsys):
    path = tmp_path / "a.h5"
    with h5py.File(path, "w") as f:
        f["wfs/open"] = X
        f["wfs/closed"] = X * 0.5
        f["wfs/time_ms"] = np.arange(1200) * 0.5
    assert main(["info", str(path)]) == 2
    _one_line_error(capsys, "a.h5", "wfs/closed, wfs/open", "--dataset PATH")
    assert main(["info", str(path), "--dataset", "wfs/closed"]) == 0
    out = capsys.readouterr().out
    assert "2000 Hz median" in out and "source_dataset: wfs/closed" in out
    np.testing.assert_allclose(_table(out)["Z3"][2], (X[:, 1] * 0.5).std(), rtol=1e-4)
    assert main(["info", str(path), "--dataset", "wfs/closed", "--rate", "1000"]) == 0
    out = capsys.readouterr().out
    assert "1000 Hz, duration 1.2 s (uniform)" in out
    assert "rate 1000 Hz given by the caller replaces the file's timestamps" in out


@pytest.mark.parametrize("kind", ["npz", "h5"])
@pytest.mark.parametrize("mmap", [True, False])
def test_info_detects_a_flipped_byte(tmp_path, capsys, kind, mmap):
    from modalinfo.io import save
    from modalinfo.telemetry import ModalLog

    path = save(ModalLog(X, rate=100.0), tmp_path / f"m.{kind}")
    extra = [] if mmap else ["--no-mmap"]
    assert main(["info", str(path), *extra]) == 0
    assert "integrity" in capsys.readouterr().out
    if kind == "h5":
        with h5py.File(path, "r") as f:
            offset = f["coefficients"].id.get_offset()
    else:
        offset = path.read_bytes().index(b"\x93NUMPY") + 128  # inside coefficients.npy
    data = bytearray(path.read_bytes())
    data[offset + X.nbytes // 2] ^= 0x01
    path.write_bytes(bytes(data))
    assert main(["info", str(path), *extra]) == 2
    _one_line_error(capsys, f"m.{kind}", "checksum" if kind == "h5" else "CRC")


def test_info_reports_clock_jitter(tmp_path, capsys):
    from scipy.stats import median_abs_deviation

    dt = 5e-4 * (1 + 0.02 * np.random.default_rng(2).standard_normal(1199))
    t = np.concatenate([[0.0], np.cumsum(dt)])
    np.savez(tmp_path / "j.npz", data=X, time=t)
    assert main(["info", str(tmp_path / "j.npz")]) == 0
    out = capsys.readouterr().out
    jitter = median_abs_deviation(np.diff(t), scale="normal") / np.median(np.diff(t))
    line = next(ln for ln in out.splitlines() if ln.startswith("sampling"))
    assert line.endswith("of the median interval; no gaps (interval > 1.5 x median)")
    shown = float(line.split("jitter ")[1].split("%")[0])  # printed to 3 digits
    assert shown == pytest.approx(100 * jitter, rel=6e-3)
    assert 1.5 < shown < 2.5  # the 2% clock noise put in
