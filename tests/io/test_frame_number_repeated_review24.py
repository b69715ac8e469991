"""A frame number written twice in a CSV (planted-bug review 24, X8; issue 27).

Reference: the refusal's own advice followed literally, as round 34's counter tests.
Frame numbers 0..99, 99, 100..199: the refusal advised ``--rate`` "so that the missing
frames show as gaps", and the file read with that rate was refused again (two frames
of one time). It now names the repeated number and its row and advises deleting the
row; the file without that row reads as 201 consecutive frames.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load

RATE = 1000.0


def _csv(path, frames, x) -> None:
    np.savetxt(path, np.column_stack([frames, x]), delimiter=",", header="frame,z2,z3",
               comments="", fmt="%.17g")


def test_a_repeated_frame_number_is_named_and_its_advice_works(tmp_path):
    frames = np.r_[np.arange(100), 99, np.arange(100, 200)]
    x = np.random.default_rng(24).normal(size=(frames.size, 2))
    _csv(tmp_path / "d.csv", frames, x)
    with pytest.raises(ValueError) as info:
        load(tmp_path / "d.csv")
    text = str(info.value)
    assert "frame 99 appears again at row 100" in text and "delete the repeated row" in text
    assert "go back" not in text and "show as gaps" not in text
    with pytest.raises(ValueError, match="strictly increasing"):
        load(tmp_path / "d.csv", rate=RATE)  # why a rate is not the advice
    keep = np.ones(frames.size, dtype=bool)
    keep[100] = False
    _csv(tmp_path / "e.csv", frames[keep], x[keep])
    log = load(tmp_path / "e.csv")
    np.testing.assert_array_equal(log.coeffs, x[keep])
