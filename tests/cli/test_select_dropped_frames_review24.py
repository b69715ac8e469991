"""Planted-bug review 24 (issue 27): ``select`` refuses frames dropped unseen in its words.

Reference: a CSV without a time axis whose frames 100 and 101 hold a NaN (written
here): ``--nonfinite drop`` removes them and leaves no gap to see. ``select`` refuses
the log before any work in the command's words - the option that removed them
(``--nonfinite drop``) and the two it can use instead (``--rate``, ``--nonfinite
interpolate``) - as ``forecast`` does; the library's rule (``require_frames_kept``)
behind it speaks of keyword arguments.
"""

from __future__ import annotations

import numpy as np

from modalinfo.cli import main


def test_select_names_the_options(tmp_path, capsys):
    data = np.random.default_rng(7).standard_normal((300, 2))
    data[100:102, 0] = np.nan
    path = tmp_path / "nan.csv"
    path.write_text("Z2,Z3\n" + "\n".join(f"{a!r},{b!r}" for a, b in data.tolist()) + "\n")
    code = main(["select", str(path), "--nonfinite", "drop", "--target", "Z2", "--max-lag",
                 "2", "--surrogates", "19", "--no-intervals", "--max-inputs", "1",
                 "--method", "gaussian"])
    err = capsys.readouterr().err
    assert code == 2 and len(err.splitlines()) == 1, err
    assert "--nonfinite drop removed frames" in err
    assert "give --rate" in err and "--nonfinite interpolate" in err
