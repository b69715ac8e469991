"""``loop_status`` of a run whose SR band holds the open loop: rose and swings, or never rose.

Issue 27, left24-status (adversarial round 24 PART a, rows K21, K22): at gain 0.05 (SR
peak from 1.07e-15 to a median of 0.206 over the second half) and 1.99 (a ringing loop,
from 4.68e-11 to a median of 0.040, mean 0.168) the status read "did not close: the SR
peak ... never rose clearly above its open-loop value", false of an SR that rose 14
orders of magnitude. References, outside the code: residual histories built here whose
SR peak ``exp(-sigma^2)`` is known by construction (a swinging SR of median ~0.2, a
three-frame ringing, an SR that rises on one frame in three, a flat one), numpy's median
and mean of their second half, the band by its documented definition (median minus
3 x 1.4826 MAD of the second half) and the documented "rose clearly" of a frame: its
residual below half the open-loop one (frame 0), counted here on the residuals.
Fast: hand-built results, no simulation.
"""

from __future__ import annotations

import numpy as np

from .test_result_views import _result

N = 100  # frames of 1 ms: the second half starts at frame 50; the first command at 1


def _band(sr: np.ndarray) -> float:
    tail = sr[N // 2:]
    med = np.median(tail)
    return float(med - 3.0 * 1.4826 * np.median(np.abs(tail - med)))


def _rose_and_swings(sr: np.ndarray) -> None:
    r = _result(-np.log(sr))
    status = r.loop_status
    tail = sr[N // 2:]
    assert status == (
        f"did not close: the SR peak rose from its open-loop value ({sr[0]:.3g}) to a median "
        f"of {np.median(tail):.3g} over the second half (mean {tail.mean():.3g}), but swings "
        f"too widely to tell a closure: the band of its second half (median - 3 robust sd) "
        f"reaches down to {_band(sr):.3g}, holding the open-loop start")
    # the verdict and its window do not move: a run that did not close, its second half
    assert r.closure_index == 0 and not r.closed and r.averaging_start == N // 2


def test_a_slow_loop_whose_sr_rose_and_swings_says_it_rose():
    # K21: gain 0.05, SR 1e-15 at frame 0, then ~0.2 swinging by +-0.15 and slowly falling
    # (its first half's mean above its second half's: not "still converging")
    k = np.arange(N)
    sr = 0.22 - 0.0004 * k + 0.15 * np.sin(2 * np.pi * k / 7)
    sr[0] = 1e-15
    assert _band(sr) < 0.0  # the band holds the open loop: a "closure" at frame 0
    _rose_and_swings(sr)


def test_a_ringing_loop_whose_sr_rose_says_it_rose():
    # K22: gain 1.99, SR 4.68e-11 at frame 0, then ringing 0.45, 0.04, 1e-9: a median
    # of 0.04 (residual 3.2 rad^2, below half the open-loop 23.8)
    sr = np.tile([0.45, 0.04, 1e-9], N // 3 + 1)[:N]
    sr[0] = 4.68e-11
    _rose_and_swings(sr)


def test_an_sr_that_rose_one_frame_in_three_says_how_often():
    # round 8's e87 as kaos at gain 0.999 rings (rerun here): 0.6 on one frame in three,
    # ~1e-8 on the others, 5e-9 at frame 0: the median stays near the open loop
    sr = np.tile([0.6, 1e-8, 1.5e-8], N // 3 + 1)[:N]
    sr[0] = 5e-9
    v = -np.log(sr)
    risen = int(np.count_nonzero(v[1:] < 0.5 * v[0]))
    assert risen == 33
    tail = sr[N // 2:]
    assert _result(v).loop_status == (
        f"did not close: the SR peak ({tail.mean():.3g} in the second half, median "
        f"{np.median(tail):.3g}) rose clearly above its open-loop value (5e-09) on only "
        f"{risen} of the {N - 1} frames after the first command: the band of its second "
        f"half (median - 3 robust sd) reaches down to {_band(sr):.3g}")


def test_an_sr_that_never_rose_still_says_so():
    # flat at 0.81 +- 0.01: no frame's residual falls below half the open-loop one
    sr = 0.81 + 0.01 * (-1.0) ** np.arange(N)
    sr[0] = 0.8
    status = _result(-np.log(sr)).loop_status
    assert status == (
        f"did not close: the SR peak ({sr[N // 2:].mean():.3g} in the second half) never "
        f"rose clearly above its open-loop value (0.8): the band of its second half (median "
        f"- 3 robust sd) reaches down to {_band(sr):.3g}")
