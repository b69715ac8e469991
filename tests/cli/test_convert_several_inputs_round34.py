"""`convert` given a night's parts to join (adversarial round 34 PART b, C03, C04).

Reference: the files on disk before and after (pathlib). ``convert a.npz b.npz j.npz``
said "unrecognized arguments: j.npz", as if a.npz -> b.npz were right and the output
name the mistake. It is one line naming every file and saying that no command joins
logs, exit 2, and no file is written or changed.
"""

from __future__ import annotations

import numpy as np

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


def test_three_files_refused_in_one_line_nothing_written(tmp_path, capsys):
    x = np.random.default_rng(34).normal(size=(400, 3))
    a, b = tmp_path / "a.npz", tmp_path / "b.npz"
    save(ModalLog(x[:200], rate=1000.0, modes=[2, 3, 4]), a)
    save(ModalLog(x[200:], rate=1000.0, modes=[2, 3, 4], start_time=0.2), b)
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    code = main(["convert", str(a), str(b), str(tmp_path / "joined.npz")])
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1
    assert "reads one log" in err and "joined.npz" in err and "no command joins" in err
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before


def test_two_files_still_convert(tmp_path):
    x = np.random.default_rng(35).normal(size=(100, 2))
    save(ModalLog(x, rate=1000.0, modes=[2, 3]), tmp_path / "a.npz")
    assert main(["convert", str(tmp_path / "a.npz"), "--units", "rad",
                 str(tmp_path / "a.csv"), "--quiet"]) == 0
    assert (tmp_path / "a.csv").is_file()
