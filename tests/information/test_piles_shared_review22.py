"""select_inputs names a shared pile just above 0.5 %, held by a target under 1 % (review 22).

Issue 27, review22 (docs/MUTATION.md, "Planted bugs, round 22", P1: the target's gate
``shared_pile_value`` raised from 0.5 % to 1 % passed test_piles_shared_left28, whose
run of zeros is 2 % of each series). Reference, outside the code: the origins at which
the target ``series[t + 1]`` and the lag-0 candidate ``series[t]`` are both 0.0,
counted by hand with numpy, against the documented shared-atom line
(``PILE_SHARED_SHARE`` = 0.5 %, at least ``PILE_MIN_COUNT`` = 5 samples). A run of 8
zero frames in 1,000 is 0.8 % of each series and 7 shared origins of 998 (0.70 %): above
the line, so it must be named, though the target holds the value under 1 %.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information.discrete import PILE_MIN_COUNT, PILE_SHARED_SHARE

from .test_piles_shared_left28 import T, _pile_messages, _shared_zero_share, _var1


def test_a_run_of_8_zero_frames_is_named():
    data = _var1()
    data[450:458] = 0.0
    assert (data[:, 1] == 0.0).mean() == pytest.approx(0.008)
    shared = _shared_zero_share(data, 1, 0, 2)
    assert shared * 998 == pytest.approx(7) and shared > PILE_SHARED_SHARE
    assert 7 >= PILE_MIN_COUNT
    got = _pile_messages(data, "histogram")
    assert len(got) == 1, got
    assert "target m1[t+h]" in got[0] and "together" in got[0]


def test_the_first_candidate_alone_sharing_the_target_s_pile_is_named():
    # P2 (review 22): the candidates' loop skipping the first passed test_piles_shared_left28,
    # where every lag-0 candidate shares the run. Here m1 (the target) is 0.0 at 9 isolated
    # frames F and m0 at F - 1 (a mode written one frame early): only m0[t], the first
    # candidate (lag-major order: m0[t], m1[t], m2[t], m0[t-1], ...), shares the target's
    # zeros, on 9 origins (0.9 %), counted by hand
    data = _var1()
    frames = (400 + 10 * np.arange(9))
    data[frames, 1] = 0.0
    data[frames - 1, 0] = 0.0
    assert _shared_zero_share(data, 1, 0, 2) * 998 == pytest.approx(9)
    origins = np.arange(1, T - 1)
    target0 = data[origins + 1, 1] == 0.0
    for src, lag in [(1, 0), (2, 0), (0, 1), (1, 1), (2, 1)]:  # the other candidates
        assert not np.any(target0 & (data[origins - lag, src] == 0.0))
    got = _pile_messages(data, "histogram")
    assert len(got) == 1, got
    assert "`target m1[t+h]` and `m0[t]`" in got[0]
