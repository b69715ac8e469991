"""``resampling.clip_glitches`` counts the values it replaced (review37, issue 27).

Reference (outside the code under test): the glitches planted by hand (+40 sd at 4
frames of one of 3 white columns, numpy seed 0) and ``numpy``'s own count of the values
that differ between the returned series and the input: the message must say that
count (4 values in 4 frames), not the count of values left alone.
"""

from __future__ import annotations

import re

import numpy as np

from modalinfo.information.resampling import clip_glitches


def test_the_message_counts_the_replaced_values():
    x = np.random.default_rng(0).standard_normal((2000, 3))
    x[[300, 900, 1500, 1800], 1] += 40.0
    out, why = clip_glitches(x, ["a", "b", "c"], "select")
    changed = out != x
    assert int(changed.sum()) == 4 and set(np.flatnonzero(changed[:, 1])) == {300, 900, 1500, 1800}
    m = re.search(r"so (\d+) value\(s\) in (\d+) frame\(s\)", why)
    assert m is not None and (int(m[1]), int(m[2])) == (4, 4)
