"""``matched_window`` against its published rule, enumerated window by window.

Reference: the end-point matching rule of Theiler et al. (Physica D 58, 77, 1992,
sec. 3) and Schreiber & Schmitz (Physica D 142, 346, 2000, sec. 4.1) as
``modalinfo.information.resampling.matched_window`` documents it, written out here by
brute force over every window ``[a, b)`` of a short series: the mismatch, summed over
the columns, is ``(v[b-1] - v[a])^2 / s1 + ((v[a+1] - v[a]) - (v[b-1] - v[b-2]))^2 / s2``
(``s1``, ``s2``: the column's mean squared first and second differences over all the
rows); of the windows that discard at most ``floor(max_discard n)`` rows, the longest
whose mismatch is at most **2 per column** (a typical step scores 1 + 1) wins, the least
mismatch among equally long ones, else the window of least mismatch overall. A zigzag
checks the per-column scale by hand: every step is +-1 and every bend +-2, so a series
that starts and ends on a rising step scores 1 + 0 per column.
"""

import itertools

import numpy as np
import pytest

from modalinfo.information.resampling import matched_window


def _brute(v: np.ndarray, max_discard: float) -> tuple[int, int] | None:
    """The rule by enumeration; None when a rounding-close call would decide it."""
    n, m = v.shape
    k = int(max_discard * n)
    s1 = np.mean(np.diff(v, axis=0) ** 2, axis=0)
    s2 = np.mean(np.diff(v, 2, axis=0) ** 2, axis=0)
    limit = 2.0 * m
    scored = []
    for a, b in itertools.product(range(n), range(n + 1)):
        if b - a < 3 or a + (n - b) > k:
            continue
        jump = v[b - 1] - v[a]
        bend = (v[a + 1] - v[a]) - (v[b - 1] - v[b - 2])
        scored.append((float(np.sum(jump ** 2 / s1 + bend ** 2 / s2)), a, b))
    if any(abs(s - limit) < 1e-9 * limit for s, _, _ in scored):
        return None
    good = [t for t in scored if t[0] <= limit]
    if good:
        longest = max(b - a for _, a, b in good)
        best = sorted(t for t in good if t[2] - t[1] == longest)
    else:
        best = sorted(scored)
    if len(best) > 1 and abs(best[0][0] - best[1][0]) < 1e-9 * max(best[0][0], 1e-300):
        return None
    return best[0][1], best[0][2]


@pytest.mark.parametrize("columns", [1, 2])
def test_windows_are_the_rule_enumerated(columns):
    rng = np.random.default_rng(20_261_128)
    checked = 0
    for _ in range(60):
        v = np.cumsum(rng.standard_normal((14, columns)), axis=0)
        want = _brute(v, 0.4)
        if want is None:
            continue
        checked += 1
        assert matched_window(*[v[:, c] for c in range(columns)], max_discard=0.4) == want
    assert checked >= 50


def test_a_zigzag_ending_on_a_typical_step_is_kept_whole():
    # steps +-1 (s1 = 1), bends +-2 (s2 = 4): rows 0..n-1 of 0, 1, 0, 1, ... with a last
    # rise of 1 and a first rise of 1: jump 1 / 1 + bend 0 / 4 = 1 per column
    v = np.tile([0.0, 1.0], 10)
    assert matched_window(v, max_discard=0.3) == (0, 20)
    # shifted by half a period in the second column: its ends score 1 + 0 as well
    assert matched_window(v, 1.0 - v, max_discard=0.3) == (0, 20)
