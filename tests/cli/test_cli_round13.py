"""Adversarial round 13, PART b (command lines, files, environment): the fixed rows.

References, all outside the code under test: the PEP 383 mapping of a non-UTF-8 file
name (``os.fsdecode`` / ``os.fsencode``) and ``ls -b``'s ``\\xNN`` spelling of such a
byte, read back by pandas and pyarrow; ``errno.ENOSPC`` (a full disk) and the bytes of
the file written before the failed save; ISO 8601 date strings written by pandas'
``strftime``; the day (86 400 s) and the nanosecond as units of a time column; the CSV
header of Python's :mod:`csv` module (a column named twice). Rows of docs/ADVERSARIAL.md
"Round 13 PART b". Each test fails on the code before its fix.
"""

from __future__ import annotations

import errno
import os

import numpy as np
import pandas as pd
import pyarrow.parquet as pq
import pytest

from modalinfo.batch.manifest import collect_logs
from modalinfo.common.files import atomic_write
from modalinfo.common.tasks.rows import write_table
from modalinfo.common.validation import log_rate_problem

from .conftest import exit_code, write_small_log


# ------------------------------------------------ B14: a file name that is not UTF-8
def test_table_holds_a_non_utf8_file_name_as_ls_shows_it(tmp_path):
    name = os.fsdecode(b"/data/bad\xff\xfename.npz")  # how Python sees the bytes (PEP 383)
    rows = [{"path": name, "n_frames": 10}, {"path": "/data/ok.npz", "n_frames": 20}]
    csv_path, pq_path = write_table(rows, tmp_path, "batch")
    expected = "/data/bad\\xff\\xfename.npz"  # ls -b
    assert pd.read_csv(csv_path)["path"].tolist() == [expected, "/data/ok.npz"]
    assert pq.read_table(pq_path).column("path").to_pylist() == [expected, "/data/ok.npz"]


# -------------------------------------------------- D01/D04/D07: a disk that fills up
@pytest.mark.parametrize("failure", [OSError(errno.ENOSPC, "No space left on device"),
                                     OSError("Not enough space on disk: requested 1728000, "
                                             "available 0. 216000 requested and 25240 "
                                             "written")])  # astropy's words, no errno
def test_full_disk_is_one_line_naming_the_file_and_keeps_the_old_one(tmp_path, failure):
    target = tmp_path / "log.csv"
    target.write_bytes(b"old contents")

    def write(fh):
        fh.write(b"partial")
        raise failure

    with pytest.raises(OSError) as info:
        atomic_write(target, write, overwrite=True)
    text = str(info.value)
    assert info.value.errno == errno.ENOSPC
    assert str(target) in text and "old file is unchanged" in text and "\n" not in text
    assert text.lower().count("space") == 2  # "No space left", "free space": said once
    assert target.read_bytes() == b"old contents"
    assert [p.name for p in tmp_path.iterdir()] == ["log.csv"]  # no temporary file left


# ------------------------------------------------- T03/T08: ISO dates in a time column
@pytest.mark.parametrize("stamp", ["%Y-%m-%dT%H:%M:%S.%f%z", "%Y-%m-%dT%H:%M:%S.%fZ",
                                   "%Y-%m-%d %H:%M:%S.%f"])
def test_csv_with_iso_times_is_named_not_corrupt(tmp_path, capsys, stamp):
    times = pd.date_range("2026-12-31T23:59:59.5", periods=50, freq="500us", tz="UTC")
    rng = np.random.default_rng(1)
    frame = pd.DataFrame({"time": times.strftime(stamp), "Z2": rng.standard_normal(50),
                          "Z3": rng.standard_normal(50)})
    path = tmp_path / "iso.csv"
    frame.to_csv(path, index=False)
    assert exit_code(["info", path, "--rate", "2000"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "corrupt" not in err
    assert "dates and times as text" in err and "seconds" in err


# ------------------------------------------- T01: MJD days read as seconds, and ns
def test_rate_hint_names_the_unit_slip_in_the_right_direction():
    days = log_rate_problem(1 / (0.0005 / 86_400), True, "mjd.csv")  # 0.5 ms in days
    ns = log_rate_problem(1 / 500_000, True, "ns.csv")  # 0.5 ms in ns
    assert "days" in days and "ns or us" not in days
    assert "ns or us" in ns and "days" not in ns


# -------------------------------------------------- B18: a manifest column named twice
def test_manifest_column_given_twice_is_refused(tmp_path):
    write_small_log(tmp_path / "a.npz", 100)
    manifest = tmp_path / "m.csv"
    manifest.write_text("path,rate,rate\na.npz,1000,2000\n")
    with pytest.raises(ValueError, match="column 'rate' appears twice"):
        collect_logs([manifest])


# ------------------------- O11/O12/O13: reorder options its --method does not use
@pytest.mark.parametrize("argv, needle", [
    (["--method", "standard", "--estimator", "ksg"], "--estimator applies"),
    (["--method", "variance", "--resamples", "10"], "--resamples applies"),
    (["--method", "pca"], "--basis kl-data"),
])
def test_reorder_refuses_an_option_its_method_ignores(tmp_path, capsys, argv, needle):
    log = write_small_log(tmp_path / "log.npz", 400)
    assert exit_code(["reorder", log, *argv]) == 2
    err = capsys.readouterr().err
    assert needle in err and err.count("\n") == 1


def test_reorder_baseline_without_those_options_still_runs(tmp_path, capsys):
    log = write_small_log(tmp_path / "log.npz", 400)
    assert exit_code(["reorder", log, "--method", "variance"]) == 0
    out = capsys.readouterr().out
    # the variance order is the order of the mean squares (numpy)
    assert "Z2" in out and "Z4" in out


def test_misspelt_manifest_column_names_the_column_meant(tmp_path):
    write_small_log(tmp_path / "a.npz", 100)
    manifest = tmp_path / "m.csv"
    manifest.write_text("path,ratee\na.npz,1000\n")
    with pytest.raises(ValueError, match=r"unknown column 'ratee' \(did you mean 'rate'\?\)"):
        collect_logs([manifest])
