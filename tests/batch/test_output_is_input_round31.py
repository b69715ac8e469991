"""Round 31 PART b (issue 27): ``batch DIR --out DIR`` names the clash, not "no logs".

docs/ADVERSARIAL.md, "Round 31 PART b, issue 27", d15: ``modalinfo batch sd --out sd``
on a folder holding two logs said "no log files found in sd" (the output directory is
never searched, and here it was the whole input).

Reference: the folder's content, counted in the test (two logs written with ``np.save``
/ ``np.savez``); the documented rule of ``collect_logs`` (the output directory is never
read); a folder whose *subfolder* is the output still yields its logs (round 19 PART b,
b12), so the refusal is for an input at or under the output only. Nothing is written.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.batch.manifest import collect_logs
from modalinfo.cli import main


def _folder(tmp_path):
    d = tmp_path / "sd"
    d.mkdir()
    x = np.random.default_rng(0).normal(size=(600, 3))
    np.save(d / "a.npy", x)
    np.save(d / "b.npy", x[::-1].copy())
    return d


def test_input_folder_equal_to_the_output_is_refused_naming_it(tmp_path):
    d = _folder(tmp_path)
    with pytest.raises(ValueError, match="is the output directory or lies inside it"):
        collect_logs([d], exclude=[d])
    with pytest.raises(ValueError, match="is the output directory or lies inside it"):
        collect_logs([d / "."], exclude=[tmp_path])  # inside it, by another spelling


def test_the_output_inside_the_input_still_finds_the_logs(tmp_path):
    d = _folder(tmp_path)
    (d / "out").mkdir()
    found = collect_logs([d], exclude=[d / "out"])
    assert sorted(e.path.rsplit("/", 1)[-1] for e in found) == ["a.npy", "b.npy"]


def test_command_line_one_line_exit_2_nothing_written(tmp_path, capsys):
    d = _folder(tmp_path)
    before = sorted(p.name for p in d.iterdir())
    code = main(["batch", str(d), "--out", str(d), "--quiet", "--no-plots", "--workers", "1"])
    assert code == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "choose another --out" in err and "no log files" not in err
    assert sorted(p.name for p in d.iterdir()) == before
