"""A frame counter that goes back in a CSV (adversarial round 34 PART b, B25, B27, B28).

Reference: the refusal's own advice followed literally. A text counter has no width,
so a wrap (65535 -> 0, 2^32 - 1 -> 0) or a restart stays refused (round 21); before,
the message advised ``--rate`` "so that the missing frames show as gaps", and the
file read with that rate was refused again (its times decrease). The refusal now
names the step back and does not advise a rate alone; a counter skipping frames
forward keeps the rate advice, which works (its gap is then read).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import load

RATE = 1000.0


def _csv(path, frames) -> None:
    x = np.random.default_rng(34).normal(size=(len(frames), 2))
    np.savetxt(path, np.column_stack([frames, x]), delimiter=",", header="frame,z2,z3",
               comments="", fmt="%.17g")


@pytest.mark.parametrize("frames", [
    (np.arange(300) + 65400) % 65536,
    (np.arange(300, dtype=np.int64) + 2**32 - 100) % 2**32,
    np.r_[np.arange(150), np.arange(150)],
])
def test_a_counter_going_back_is_not_advised_a_rate(tmp_path, frames):
    _csv(tmp_path / "c.csv", frames)
    with pytest.raises(ValueError) as info:
        load(tmp_path / "c.csv")
    text = str(info.value)
    assert "go back" in text and "which no rate turns into times" in text
    row = int(np.flatnonzero(np.diff(frames) < 0)[0]) + 1
    assert f"split the file at row {row}" in text
    with pytest.raises(ValueError, match="strictly increasing"):
        load(tmp_path / "c.csv", rate=RATE)  # why a rate alone is not the advice


def test_a_counter_skipping_forward_keeps_the_rate_advice(tmp_path):
    frames = np.r_[np.arange(100), np.arange(105, 300)]
    _csv(tmp_path / "g.csv", frames)
    with pytest.raises(ValueError, match="not consecutive \\(99 then 105.*--rate"):
        load(tmp_path / "g.csv")
    assert load(tmp_path / "g.csv", rate=RATE).sampling().n_gaps == 1
