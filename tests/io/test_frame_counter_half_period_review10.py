"""A fixed-width frame counter wraps only on a step down of more than half its period.

Round 10 of planted bugs (review10). Reference (another library): ``numpy.unwrap`` with
``period = 2**w`` (its rule: a step beyond half the period is a wrap), applied to the
counter of an 8-bit column. A ``uint8`` counter restarting at 0 after 100 frames steps
down by 99, less than 128: numpy.unwrap leaves it a step down, so the counter is not
consecutive and the log is refused, with or without a rate, as the issue-27 leftovers'
rule says for a counter restarting after 999 frames in 16 bits. Planted bug R10-X2
(a wrap from a quarter of the period, 64) escaped tests/io/test_frame_counter_wrap.py,
whose restart (999 in 16 bits) is far below both: this log was unwrapped into a gap of
156 frames and accepted.
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest

from modalinfo.io import load


@pytest.mark.parametrize("fmt", ["npz", "h5"])
def test_an_8_bit_counter_restarting_after_100_frames_is_not_a_wrap(tmp_path, fmt):
    counter = np.concatenate([np.arange(100), np.arange(100)]).astype(np.uint8)
    unwrapped = np.unwrap(counter.astype(np.float64), period=256)
    assert np.diff(unwrapped).min() == -99  # numpy: no wrap, a step down
    x = np.random.default_rng(10).standard_normal((200, 3))
    path = tmp_path / f"r.{fmt}"
    if fmt == "npz":
        np.savez(path, coefficients=x, frame=counter)
    else:
        with h5py.File(path, "w") as f:
            f["coefficients"] = x
            f["frame"] = counter
    with pytest.raises(ValueError, match="frame numbers are not consecutive"):
        load(path)
    with pytest.raises(ValueError, match="strictly increasing"):
        load(path, rate=1000.0)
