"""Hand-written batch manifests (adversarial round 20 PART b, issue 27).

References: the CSV dialect as Python's ``csv`` module and a spreadsheet write it (a
quoted cell keeps its spaces; a row longer than its header holds cells no column
names); the file system (which files exist beside the manifest); the rules of
``ModalLog`` for a rate (> 0, finite), a wavelength (100 nm - 100 um) and a unit (one
of rad, nm, um, waves), stated in its docstring, not derived from the code under test.
Each input was accepted silently, or refused late with a misleading message, before
the fixes.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from modalinfo.batch.manifest import collect_logs
from modalinfo.io import load, save
from modalinfo.telemetry.log import ModalLog


def _logs(folder: Path, *names: str) -> None:
    for name in names:
        np.save(folder / name, np.zeros((8, 3)))


def _manifest(folder: Path, text: str) -> Path:
    path = folder / "m.csv"
    path.write_text(text, encoding="utf-8", newline="")
    return path


def test_a_log_whose_name_starts_with_hash_is_not_dropped_as_a_comment(tmp_path):
    # B06: '#h.npy' was skipped as a comment line, exit 0, its row absent, no word
    _logs(tmp_path, "#h.npy", "a.npy")
    with pytest.raises(ValueError, match=r"starts with '#'.*#h\.npy.*quote"):
        collect_logs(_manifest(tmp_path, "path\n#h.npy\na.npy\n"))
    # quoted, it is read; a real comment is still skipped
    entries = collect_logs(_manifest(tmp_path, 'path\n"#h.npy"\n# a note\na.npy\n'))
    assert [Path(e.path).name for e in entries] == ["#h.npy", "a.npy"]


def test_a_quoted_leading_space_names_the_file_as_written(tmp_path):
    # B09: '" sp.npy"' was stripped to 'sp.npy': "no such file", the file beside it
    _logs(tmp_path, " sp.npy")
    entries = collect_logs(_manifest(tmp_path, 'path\n" sp.npy"\n'))
    assert [Path(e.path).name for e in entries] == [" sp.npy"]


def test_cells_beyond_the_header_are_refused_naming_the_row(tmp_path):
    # B13: 'a.npy,2000' under the header 'path' lost the 2000 without a word
    _logs(tmp_path, "a.npy")
    with pytest.raises(ValueError, match=r"row 2: 1 cell\(s\) beyond.*'2000'"):
        collect_logs(_manifest(tmp_path, "path\na.npy,2000\n"))
    # a spreadsheet's empty trailing cells say nothing and are accepted
    assert len(collect_logs(_manifest(tmp_path, "path\na.npy,,\n"))) == 1


@pytest.mark.parametrize(("column", "value", "rule"), [
    ("rate", "-5", r"column 'rate' must be > 0"),
    ("rate", "nan", r"column 'rate' must be finite"),
    ("rate", "inf", r"column 'rate' must be finite"),
    ("wavelength", "0", r"column 'wavelength' must be > 0"),
    ("units", "furlong", r"column 'units' must be one of"),
    ("convention", "zzz", r"column 'convention' must be one of"),
    ("nonfinite", "zzz", r"column 'nonfinite' must be one of"),
    ("fmt", "xls", r"column 'fmt' must be one of"),
])
def test_impossible_hints_are_refused_before_work_naming_the_row(tmp_path, column, value, rule):
    # B15-B21: accepted at reading, then an error row per log "contradicts the value
    # 2000.0 stored" (or a late "`fmt` must be ...") after the cluster started
    _logs(tmp_path, "a.npy")
    with pytest.raises(ValueError, match=rf"row 2: {rule}"):
        collect_logs(_manifest(tmp_path, f"path,{column}\na.npy,{value}\n"))


def test_a_manifest_naming_a_manifest_is_refused(tmp_path):
    # B22 / B23: read as a log, "corrupt CSV file ... could not convert 'a.npy'"
    _logs(tmp_path, "a.npy")
    (tmp_path / "inner.csv").write_text("path\na.npy\n", encoding="utf-8")
    with pytest.raises(ValueError, match=r"row 2: 'inner\.csv' is a manifest"):
        collect_logs(_manifest(tmp_path, "path\ninner.csv\n"))
    with pytest.raises(ValueError, match=r"row 2: 'm\.csv' is a manifest"):
        collect_logs(_manifest(tmp_path, "path\nm.csv\n"))


def test_a_latin1_manifest_is_refused_naming_the_file_and_the_remedy(tmp_path):
    # B30: "'utf-8' codec can't decode byte 0xfc in position 5" and nothing else
    _logs(tmp_path, "\u00fc.npy")
    path = tmp_path / "m.csv"
    path.write_bytes("path\n\u00fc.npy\n".encode("latin-1"))
    with pytest.raises(ValueError, match=r"m\.csv' is not UTF-8 text.*re-save it as UTF-8"):
        collect_logs(path)


def test_load_names_an_impossible_hint_before_comparing_it_with_the_file(tmp_path):
    # the API road of B15: load(path, rate=-5) said "contradicts the value 2000.0 stored"
    log = ModalLog(np.zeros((16, 3)), rate=2000.0)
    path = save(log, tmp_path / "a.npz")
    with pytest.raises(ValueError, match=r"`rate` must be > 0"):
        load(path, rate=-5.0)
    assert load(path, rate=2000.0).rate == 2000.0
