"""Command-line tests of ``modalinfo info`` and ``modalinfo convert``.

References: the printed statistics are checked against NumPy (mean, RMS) and
statsmodels' ``acf`` (lag-1 autocorrelation) on the same data; conversions
against the unit definitions (500 nm at 500 nm = 2 pi rad) and the Noll -> ANSI
table; error paths against the dispatcher contract (one line on stderr, exit 2,
no traceback), including in a real subprocess.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from statsmodels.tsa.stattools import acf

from modalinfo.cli import main
from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog


@pytest.fixture
def log_file(tmp_path):
    rng = np.random.default_rng(0)
    x = np.zeros((2000, 3))
    for t in range(1, 2000):
        x[t] = np.array([0.2, 0.6, 0.9]) * x[t - 1] + rng.standard_normal(3)
    log = ModalLog(
        x,
        rate=1000.0,
        units="rad",
        wavelength=5e-7,
        metadata={"loop": "closed", "telescope": "LOST"},
    )
    return save(log, tmp_path / "log.npz"), x


def _table(out: str) -> dict[str, list[float]]:
    rows = {}
    lines = out.splitlines()
    start = next(i for i, line in enumerate(lines) if line.split()[:1] == ["mode"])
    for line in lines[start + 1 :]:
        parts = line.split()
        rows[parts[0]] = [float(p) for p in parts[1:]]
    return rows


def test_info_prints_summary(log_file, capsys):
    path, x = log_file
    assert main(["info", str(path), "--chunk-frames", "123"]) == 0
    out = capsys.readouterr().out
    assert "2000 frames x 3 modes (float64)" in out
    assert "1000 Hz, duration 2 s" in out
    assert "Z2, Z3, Z4 (noll)" in out
    assert "rad at wavelength 5e-07 m" in out
    assert "loop        closed" in out and "telescope: LOST" in out
    table = _table(out)
    for k, label in enumerate(["Z2", "Z3", "Z4"]):
        mean, rms, std, lag1 = table[label]
        assert mean == pytest.approx(x[:, k].mean(), rel=1e-4, abs=1e-6)
        assert rms == pytest.approx(np.sqrt((x[:, k] ** 2).mean()), rel=1e-4)
        assert std == pytest.approx(x[:, k].std(), rel=1e-4)
        assert lag1 == pytest.approx(acf(x[:, k], nlags=1, fft=False)[1], abs=1e-4)


def test_info_foreign_npy_with_hints(tmp_path, capsys):
    np.save(tmp_path / "a.npy", np.ones((10, 2)))
    assert main(["info", str(tmp_path / "a.npy"), "--rate", "50", "--modes", "4-5", "--quiet"]) == 0
    out = capsys.readouterr().out
    # integer modes given, convention and units not: both are marked as assumed
    assert "50 Hz" in out and "Z4, Z5 (noll, assumed)" in out and "rad (assumed)" in out
    assert main(["info", str(tmp_path / "a.npy"), "--modes", "KL1,KL2"]) == 0
    out = capsys.readouterr().out
    assert "rate        unknown (pass --rate)" in out and "KL1, KL2 (labels)" in out


def test_info_reports_repairs(tmp_path, capsys):
    (tmp_path / "n.csv").write_text("1,2\nnan,3\n4,5\n")
    assert main(["info", str(tmp_path / "n.csv"), "--nonfinite", "drop", "--rate", "1"]) == 0
    assert "repair      nonfinite='drop': dropped 1 frame(s)" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["info", "{tmp}/missing.npz"], "no such file"),
        (["info", "{tmp}"], "is a directory"),
        (["info", "{tmp}/bad.npz"], "corrupt NPZ file"),
        (["info", "{tmp}/n.csv"], "must be finite"),
        (["info", "{tmp}/log.npz", "--rate", "5"], "hint --rate 5.0 contradicts"),
        (["info", "{tmp}/log.npz", "--chunk-frames", "0"], "--chunk-frames must be >= 1"),
        (["info", "{tmp}/log.npz", "--in-modes", "4,KL"], "--in-modes mixes indices and labels"),
        # the same file is refused first: --overwrite, the other refusal's advice, would
        # be refused too (round 44 PART b, after d22)
        (["convert", "{tmp}/log.npz", "{tmp}/log.npz"], "is the input file IN"),
        (["convert", "{tmp}/log.npz", "{tmp}/bad.npz"], "exists; pass --overwrite to replace it"),
        (["convert", "{tmp}/log.npz", "{tmp}/o.xls"], "cannot tell the log format"),
        (
            ["convert", "{tmp}/log.npz", "{tmp}/o.csv", "--units", "nm", "--wavelength", "6e-7"],
            "differs from the wavelength",
        ),
    ],
)
def test_errors_are_one_line_exit_2(tmp_path, log_file, capsys, argv, message):
    (tmp_path / "bad.npz").write_bytes(b"PK\x03\x04garbage")
    (tmp_path / "n.csv").write_text("1,2\nnan,3\n")
    argv = [a.format(tmp=tmp_path) for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err and "Traceback" not in err
    assert err.startswith(f"modalinfo {argv[0]}: error: ")


def test_convert_units_convention_and_format(log_file, tmp_path, capsys):
    path, x = log_file
    out = tmp_path / "out.csv"
    assert main(["convert", str(path), str(out), "--units", "nm", "--convention", "ansi"]) == 0
    assert "wrote" in capsys.readouterr().out
    log = load(out)
    assert log.units == "nm" and log.convention == "ansi"
    assert log.modes == [1, 2, 4]  # Noll 3 -> ANSI 1, Noll 2 -> ANSI 2, Noll 4 -> ANSI 4
    # 1 rad at 500 nm is 500 / (2 pi) nm
    np.testing.assert_allclose(log.coeffs[:, 1], x[:, 0] * 500.0 / (2 * np.pi), rtol=1e-14)
    np.testing.assert_allclose(log.coeffs[:, 0], x[:, 1] * 500.0 / (2 * np.pi), rtol=1e-14)
    # back to NPZ in rad/noll: values within rounding of the original
    back = tmp_path / "back.h5"
    assert (
        main(["convert", str(out), str(back), "--units", "rad", "--convention", "noll", "--quiet"])
        == 0
    )
    assert capsys.readouterr().out == ""
    np.testing.assert_allclose(load(back).coeffs, x, rtol=1e-13)
    # same content, no change: lossless format conversion
    assert main(["convert", str(path), str(tmp_path / "same.fits")]) == 0
    np.testing.assert_array_equal(load(tmp_path / "same.fits").coeffs, x)
    assert main(["convert", str(path), str(tmp_path / "same.fits"), "--overwrite"]) == 0


def test_convert_foreign_records_wavelength(tmp_path):
    np.save(tmp_path / "a.npy", np.full((4, 1), 500.0))
    argv = [
        "convert",
        str(tmp_path / "a.npy"),
        str(tmp_path / "w.npz"),
        "--in-units",
        "nm",
        "--units",
        "waves",
        "--wavelength",
        "5e-7",
        "--rate",
        "10",
        "--quiet",
    ]
    assert main(argv) == 0
    log = load(tmp_path / "w.npz")
    np.testing.assert_allclose(log.coeffs, 1.0, rtol=1e-15)
    assert log.units == "waves" and log.wavelength == 5e-7 and log.rate == 10.0


def test_subprocess_exit_code_and_stderr(tmp_path):
    (tmp_path / "bad.fits").write_bytes(b"SIMPLE  = garbage" + b" " * 100)
    result = subprocess.run(
        [sys.executable, "-m", "modalinfo", "info", str(tmp_path / "bad.fits")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 2
    assert result.stderr.count("\n") == 1
    assert result.stderr.startswith("modalinfo info: error: corrupt FITS file")
    assert result.stdout == ""


def test_subprocess_success(tmp_path):
    # 200 white frames: long enough for the quality pass, which notes shorter logs
    x = np.random.default_rng(0).standard_normal((200, 2))
    save(ModalLog(x, rate=2.0), tmp_path / "a.npz")
    result = subprocess.run(
        [sys.executable, "-m", "modalinfo", "info", str(tmp_path / "a.npz")],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    assert "200 frames x 2 modes" in result.stdout
    assert result.stderr == ""  # not a tty: no progress bar


def test_option_choices_match_the_library():
    """The CLI spells its choices out (no numpy at parser build); they must not drift."""
    import argparse

    from modalinfo.cli import build_parser
    from modalinfo.io import FORMATS
    from modalinfo.telemetry import CONVENTIONS, NONFINITE_POLICIES, UNITS

    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))

    def choices(command, option):
        action = next(a for a in sub.choices[command]._actions if option in a.option_strings)
        return tuple(action.choices)

    for command in ("info", "convert"):
        assert choices(command, "--fmt") == FORMATS
        assert choices(command, "--in-units") == UNITS
        assert choices(command, "--in-convention") == CONVENTIONS
        assert choices(command, "--nonfinite") == NONFINITE_POLICIES
    assert set(choices("convert", "--units")) == set(UNITS)
    assert set(choices("convert", "--convention")) == set(CONVENTIONS) - {"labels"}
    assert set(choices("convert", "--to-fmt")) == set(FORMATS) - {"npy"}

    from modalinfo.information.api import METHODS as ESTIMATORS
    from modalinfo.ordering.compare import BASES
    from modalinfo.ordering.orderings import METHODS

    assert set(choices("reorder", "--estimator")) == set(ESTIMATORS)
    assert set(choices("reorder", "--basis")) == set(BASES)
    assert set(choices("reorder", "--method")) == set(METHODS)
    assert set(choices("fitting-error", "--estimator")) == set(ESTIMATORS)


def test_info_says_when_lag1_pairs_frames_across_gaps(tmp_path, capsys):
    # Reference: the time axis by construction: 1500 frames at 2 kHz, then 1500 at
    # 1 kHz: 1499 of the 2999 successive pairs are not one (median) interval apart,
    # which the lag1 column did not say (audit 10-time). A uniform log gets no note.
    x = np.random.default_rng(0).standard_normal((3000, 2))
    t = np.r_[np.arange(1500) / 2000.0, 0.7495 + np.arange(1, 1501) / 1000.0]
    save(ModalLog(x, timestamps=t), tmp_path / "two.npz")
    save(ModalLog(x, rate=2000.0), tmp_path / "one.npz")
    assert main(["info", str(tmp_path / "two.npz")]) == 0
    assert "1499 of the 2999 pairs (50%) lie across gaps or rate changes" in (
        capsys.readouterr().out)
    assert main(["info", str(tmp_path / "one.npz")]) == 0
    assert "lag1 pairs" not in capsys.readouterr().out


def test_info_names_a_block_written_twice(tmp_path, capsys):
    # Reference: frames 1000..1099 written twice by construction, no timestamps
    x = np.random.default_rng(0).standard_normal((3000, 2))[np.r_[0:1100, 1000:3000]]
    save(ModalLog(x, rate=2000.0), tmp_path / "twice.npz")
    assert main(["info", str(tmp_path / "twice.npz")]) == 0
    assert "frames 1100..1199 repeat frames 1000..1099 exactly" in capsys.readouterr().out
