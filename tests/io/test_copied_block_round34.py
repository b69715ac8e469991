"""A block of frames written twice, with its timestamps (adversarial round 34 PART b, B41).

Reference: the file's own rows (numpy equality of times and values). The last 2000
frames of an 8000-frame 2 kHz log appended again with their times: refused before for
its decreasing times, with the advice to pass a rate - which read the copy as 2000 new
frames (10000 frames, 5 s) without a word. The refusal now names the copied frames
(rows 8000..9999 = rows 6000..7999) with or without a rate. A clock that restarts at 0
over new data keeps its rule (refused; a rate replaces it).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load

RATE = 2000.0


def _csv(path, t, x) -> None:
    names = ",".join(f"z{m}" for m in range(2, 2 + x.shape[1]))
    np.savetxt(path, np.column_stack([t, x]), delimiter=",", header="time," + names,
               comments="", fmt="%.17g")


@pytest.mark.parametrize("rate", [None, RATE])
def test_a_block_written_twice_is_named(tmp_path, rate):
    x = np.random.default_rng(34).normal(size=(800, 3))
    t = np.arange(800) / RATE
    _csv(tmp_path / "twice.csv", np.r_[t, t[600:]], np.r_[x, x[600:]])
    with pytest.raises(ValueError, match=r"frames 800\.\.999 repeat frames 600\.\.799 .*"
                                         r"delete those 200 rows"):
        load(tmp_path / "twice.csv", rate=rate)


def test_a_clock_restarting_over_new_frames_keeps_its_rule(tmp_path):
    x = np.random.default_rng(35).normal(size=(800, 3))
    t = np.arange(800) / RATE
    _csv(tmp_path / "restart.csv", np.r_[t[:500], t[:300]], x)
    with pytest.raises(ValueError, match="not strictly increasing"):
        load(tmp_path / "restart.csv")
    log = load(tmp_path / "restart.csv", rate=RATE)
    np.testing.assert_array_equal(log.coeffs, x)
