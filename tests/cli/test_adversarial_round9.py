"""Adversarial round 9, PART b (command lines, files, environment): the fixed rows.

References, all outside the code under test: POSIX file-creation semantics (a new file's
mode is ``0o666 & ~umask``; a replaced file keeps the mode its owner gave it); the
constructed timestamps and frame numbers of each test's own file (a log of 2000 frames
at 2 kHz followed by 2000 at 1 kHz has 1999 intervals of half the median; frames
100-109 missing is one break); ``python -OO`` semantics (docstrings are None); the
arithmetic of Unix nanoseconds (500,000 ns per frame read as seconds is 2e-6 Hz); the
sums of squared unit-RMS Zernike coefficients (the continuous fitting error) against a
16-pixel pupil's; rows of docs/ADVERSARIAL.md "Round 9 PART b". Each test fails on the
code before its fix (named in the row).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from modalinfo.io import save
from modalinfo.telemetry import ModalLog

from .conftest import exit_code, write_small_log

ROOT = Path(__file__).resolve().parents[2]


def _umask(mask: int) -> int:
    return os.umask(mask)


# ------------------------------------------------------------------ E06, E08: modes
def test_a_saved_log_follows_the_umask_and_a_replaced_file_keeps_its_mode(tmp_path):
    log = ModalLog(np.zeros((10, 2)), rate=100.0, modes=[2, 3], units="rad")
    old = _umask(0o077)
    try:
        save(log, tmp_path / "private.npz")
    finally:
        _umask(old)
    assert (tmp_path / "private.npz").stat().st_mode & 0o777 == 0o600  # was 0o644
    kept = tmp_path / "kept.csv"
    save(log, kept)
    os.chmod(kept, 0o640)
    save(log, kept, overwrite=True)
    assert kept.stat().st_mode & 0o777 == 0o640  # was 0o644 after the overwrite


# -------------------------------------------------------- M05: a folder is not replaced
def test_forecast_out_refuses_an_output_name_taken_by_a_folder(tmp_path, capsys):
    log = write_small_log(tmp_path / "log.npz", 400)
    (tmp_path / "o" / "forecast.csv").mkdir(parents=True)
    keep = tmp_path / "o" / "forecast.csv" / "keep.txt"
    keep.write_text("precious")
    code = exit_code(["forecast", log, "--predictors", "linear", "--horizon", "1",
                      "--out", tmp_path / "o", "--overwrite", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "is a folder" in err
    assert keep.read_text() == "precious"  # was deleted with the staging folder


# -------------------------------------------------------- E15, E17, E20: environment
def _run(args, **env):
    return subprocess.run([sys.executable, *args], capture_output=True, text=True,
                          env=dict(os.environ, PYTHONPATH=str(ROOT), **env), timeout=600)


@pytest.mark.parametrize("warnings", ["default", "error"])
def test_a_numba_variable_that_does_not_parse_is_one_line(tmp_path, warnings):
    log = write_small_log(tmp_path / "log.npz", 50)
    r = _run(["-m", "modalinfo", "info", str(log), "--quiet"], NUMBA_NUM_THREADS="abc",
             PYTHONWARNINGS=warnings)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert r.stderr.count("\n") == 1 and "NUMBA_NUM_THREADS" in r.stderr


def test_paper_figures_runs_with_docstrings_stripped():
    r = _run(["-OO", "-m", "paper_figures", "--help"])
    assert r.returncode == 0 and "Traceback" not in r.stderr
    assert "usage: python -m paper_figures" in r.stdout


# ------------------------------------------------- A01, A02, A14, K06, K07: time axes
def _csv(path: Path, first: str, times, data) -> Path:
    rows = zip(times, data, strict=True)
    lines = [first + ",Z2,Z3"] + [f"{t!r},{a!r},{b!r}" for t, (a, b) in rows]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_log_of_two_frame_rates_is_named_and_not_forecast(tmp_path, capsys):
    data = np.random.default_rng(0).standard_normal((4000, 2)).tolist()
    t = np.concatenate([np.arange(2000) / 2000.0, 0.9995 + (1 + np.arange(2000)) / 1000.0])
    path = _csv(tmp_path / "two.csv", "time", t.tolist(), data)
    assert exit_code(["info", path, "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "1999 interval(s) shorter than 1/1.5 of the median" in out  # was "no gaps"
    assert "longest equally spaced segment frames 1999..3999" in out
    code = exit_code(["forecast", path, "--predictors", "linear", "--horizon", "1",
                      "--out", tmp_path / "fc"])
    err = capsys.readouterr().err
    assert code == 2 and "the frame rate changes" in err and "--split-gaps" in err
    assert not (tmp_path / "fc").exists()


def test_batch_rows_state_the_median_rate_and_the_sampling():
    from modalinfo.batch.analyses import log_columns

    t = np.concatenate([np.arange(20) / 2000.0, 0.0095 + (1 + np.arange(20)) / 1000.0])
    row = log_columns(ModalLog(np.zeros((40, 1)), timestamps=t, modes=[2]))
    assert row["median_rate"] == pytest.approx(1000.0, rel=1e-9)
    assert "19 interval(s) shorter" in row["sampling"]
    uniform = log_columns(ModalLog(np.zeros((40, 1)), timestamps=np.arange(40) / 1e3,
                                   modes=[2]))
    assert uniform["sampling"] == "uniform"


def test_info_refuses_unix_nanoseconds_read_as_seconds(tmp_path, capsys):
    data = np.random.default_rng(1).standard_normal((50, 2)).tolist()
    ns = [1_764_380_000_000_000_000 + k * 500_000 for k in range(50)]  # 2 kHz in ns
    path = _csv(tmp_path / "ns.csv", "time", ns, data)
    assert exit_code(["info", path, "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "frame rate of 2e-06 Hz" in err
    assert exit_code(["info", path, "--rate", "2000", "--quiet"]) == 0


def test_frame_numbers_that_skip_are_refused_without_a_rate(tmp_path, capsys):
    data = np.random.default_rng(2).standard_normal((300, 2)).tolist()
    frames = [k for k in range(310) if not 100 <= k < 110]
    path = _csv(tmp_path / "f.csv", "frame", frames, data)
    code = exit_code(["forecast", path, "--predictors", "linear", "--horizon", "1",
                      "--out", tmp_path / "fc"])  # was forecast across the hole
    err = capsys.readouterr().err
    assert code == 2 and "not consecutive (99 then 110" in err and "--rate" in err
    assert exit_code(["info", path, "--rate", "1000", "--quiet"]) == 0
    assert "1 gap(s)" in capsys.readouterr().out


# ------------------------------------------------------------ F11: --frame of the file
def test_frame_is_a_frame_of_the_file_with_max_frames(tmp_path, capsys):
    log = write_small_log(tmp_path / "log.npz", 400)
    # (no --quiet: fitting-error's prints nothing and needs --plot since fix57-d)
    base = ["fitting-error", log, "--orderings", "zernike:standard", "--pupil-pixels", "64"]
    assert exit_code([*base, "--frame", "200"]) == 0
    whole = capsys.readouterr().out
    assert exit_code([*base, "--frame", "200", "--max-frames", "10"]) == 0  # every 40th
    sub = capsys.readouterr().out
    assert "frame 200" in sub and sub == whole  # was frame 5 x 40 = 200 of "--frame 5"
    assert exit_code([*base, "--frame", "5", "--max-frames", "10"]) == 2
    assert "not among the frames --max-frames 10 analyses" in capsys.readouterr().err


# ------------------------------------------------------- L02: a coarse pupil is noted
def test_fitting_error_notes_a_pupil_too_coarse_for_orthonormal_zernikes(tmp_path, capsys):
    rng = np.random.default_rng(3)
    coeffs = rng.standard_normal((200, 27)) * 0.05
    log = save(ModalLog(coeffs, rate=1000.0, modes=list(range(2, 29)), units="rad"),
               tmp_path / "z.npz")
    base = ["fitting-error", log, "--orderings", "zernike:standard", "--error-units", "rad2"]
    assert exit_code([*base, "--pupil-pixels", "16"]) == 0
    captured = capsys.readouterr()
    total = float(captured.out.split("dPhi(0) = ")[1].split()[0])
    exact = float(np.mean(coeffs**2, axis=0).sum())  # unit-RMS Zernikes: sum of a_k^2
    assert abs(total / exact - 1) > 0.02  # the 16-pixel pupil's error is not the exact one
    assert "not orthonormal" in captured.err  # ... and it is now said
    assert exit_code([*base, "--pupil-pixels", "64"]) == 0
    captured = capsys.readouterr()
    total = float(captured.out.split("dPhi(0) = ")[1].split()[0])
    assert abs(total / exact - 1) < 0.07
    # fix33-a: the 64-pixel Gram error (0.034) still moves the curve's tail by > 1 %,
    # said in one line naming the grid that brings it below 1e-2; at 256 pixels not
    assert captured.err.count("\n") == 1 and "not orthonormal" in captured.err
    assert "--pupil-pixels" in captured.err
    assert exit_code([*base, "--pupil-pixels", "256"]) == 0
    assert capsys.readouterr().err == ""


# ----------------------------------------------------------------- F07: JSON is JSON
def test_a_json_result_fed_back_as_a_log_is_named_json(tmp_path, capsys):
    (tmp_path / "forecast.json").write_text('{"names": ["persistence"]}\n')
    assert exit_code(["info", tmp_path / "forecast.json"]) == 2
    err = capsys.readouterr().err
    assert "holds JSON" in err and "CSV" not in err.split("not a log")[0]


# ------------------------------------------ N14, N16: a mode list that does not fit
def test_a_foreign_mode_list_of_the_wrong_length_is_refused(tmp_path, capsys):
    import h5py

    coeffs = np.random.default_rng(4).standard_normal((300, 3))
    np.savez(tmp_path / "m.npz", coefficients=coeffs, modes=np.array([2, 3]))
    with h5py.File(tmp_path / "m.h5", "w") as f:
        f.create_dataset("coeffs", data=coeffs).attrs["modes"] = np.array([2, 3])
    for name in ("m.npz", "m.h5"):  # were read as "Z2, Z3, Z4 (assumed)"
        assert exit_code(["info", tmp_path / name, "--rate", "1000", "--quiet"]) == 2
        err = capsys.readouterr().err
        assert "lists 2 mode(s) for data of shape (300, 3)" in err and "--in-modes" in err
        assert exit_code(["info", tmp_path / name, "--rate", "1000", "--in-modes", "5-7",
                          "--quiet"]) == 0
        assert "Z5, Z6, Z7" in capsys.readouterr().out


# ------------------------------------------------ N24: too few bootstrap replicates
def test_reorder_cautions_that_two_replicates_understate_the_noise(tmp_path, capsys):
    # the range of R replicates covers a new draw with probability (R - 1) / (R + 1)
    # (order statistics): 1/3 at R = 2, below any "95 %" bound
    log = write_small_log(tmp_path / "log.npz", 400)
    base = ["reorder", log, "--pupil-pixels", "16", "--budget", "500"]
    assert exit_code([*base, "--resamples", "2"]) == 0
    assert "caution: 2 replicates are too few for 95% bounds" in capsys.readouterr().out
    # the one rule of every bootstrap bound (issue 27): 2 / (1 - 0.95) = 40 replicates
    assert exit_code([*base, "--resamples", "39"]) == 0
    assert "caution: 39 replicates are too few for 95% bounds" in capsys.readouterr().out
    assert exit_code([*base]) == 0  # the default, 40
    out = capsys.readouterr().out
    assert "caution" not in out and "40 replicates" in out


# a random-walk / smooth test log: its lagged MI holds < 20 effective samples, which
# select_inputs warns since fixes 40-a (the effective-sample rule); not this test's point
@pytest.mark.filterwarnings("ignore::modalinfo.information.methods.BiasRuleWarning")
# ------------------------------------------------------- N32: one note, said once
def test_select_with_extra_and_max_frames_notes_the_subsample_once(tmp_path, capsys):
    log = write_small_log(tmp_path / "log.npz", 400)
    rng = np.random.default_rng(6)
    extra = save(ModalLog(rng.standard_normal((400, 1)), rate=2000.0, modes=[40],
                          units="rad"), tmp_path / "extra.npz")
    assert exit_code(["select", log, "--target", "Z2", "--extra", extra, "--max-frames", "200",
                      "--max-lag", "2", "--surrogates", "19", "--no-intervals",
                      "--max-inputs", "1", "--method", "gaussian"]) == 0
    err = capsys.readouterr().err
    assert err.count("--max-frames 200: analysed frames 0..199 of 400") == 1  # was twice


# ---------------------------------- N40, N42, N43: lags across removed or missing frames
def _nan_csv(path: Path) -> Path:
    data = np.random.default_rng(7).standard_normal((300, 2))
    data[100:102, 0] = np.nan  # two frames removed by --nonfinite drop
    lines = ["Z2,Z3"] + [f"{a!r},{b!r}" for a, b in data.tolist()]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_frames_dropped_without_a_rate_are_not_bridged(tmp_path, capsys):
    path = _nan_csv(tmp_path / "nan.csv")
    common = ["--nonfinite", "drop", "--out", tmp_path / "fc", "--predictors", "linear",
              "--horizon", "1"]
    assert exit_code(["forecast", path, *common]) == 2  # was forecast across frames 100-101
    assert "without a time axis" in capsys.readouterr().err
    select = ["select", path, "--nonfinite", "drop", "--target", "Z2", "--max-lag", "2",
              "--surrogates", "19", "--no-intervals", "--max-inputs", "1", "--method",
              "gaussian"]
    assert exit_code(select) == 2
    assert "without a time axis" in capsys.readouterr().err
    assert exit_code([*select, "--rate", "1000"]) == 2  # now a gap of 3 intervals
    assert "1 timestamp gap(s)" in capsys.readouterr().err  # forecast's words (fix33-b1)
    assert exit_code(["fitting-error", path, "--nonfinite", "drop", "--orderings",
                      "zernike:standard", "--pupil-pixels", "64"]) == 0  # per frame


# --------------------------------------------- N44, N46: text in another encoding
@pytest.mark.parametrize(("encoding", "extra"), [("cp1252", ""), ("utf-16", "UTF-16 text")])
def test_a_csv_in_another_encoding_is_named_as_such(tmp_path, capsys, encoding, extra):
    text = "Z2 [\xb5m],Z3 [\xb5m]\n" + "0.1,0.2\n" * 20
    (tmp_path / "w.csv").write_bytes(text.encode(encoding))
    assert exit_code(["info", tmp_path / "w.csv", "--rate", "1000"]) == 2
    err = capsys.readouterr().err
    assert "a CSV must be UTF-8" in err and extra in err  # was "neither text (CSV)"
