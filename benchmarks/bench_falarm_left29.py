"""False alarms of each stationarity rule of ``assess_quality`` (issue 27, left29-falarm).

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_falarm_left29.py PHI FRAMES [SEEDS]

Stationary AR(1) logs (coefficient PHI, 10 independent modes of unit marginal variance,
``10 / (1 - PHI)`` frames of burn-in, seeds ``[29, s]`` for s < SEEDS, default 200) of
FRAMES frames are assessed by :func:`modalinfo.telemetry.assess_quality`; per log, which
rule named anything: the level rule (``level_steps``, stated family-wise 1 %,
``LEVEL_ALPHA``), the spread rule (``variance_steps`` on the absolute deviations,
0.25 %, ``VARIANCE_ALPHA``), the spread at the level step (``spread_at_split``, 0.25 %,
run only where the level rule fired), the per-mode scale rule (``scale_steps``, 0.1 %)
and the block-scale ratio (``scale_ratio`` beyond ``stationarity_threshold``, 1 %).
Every p-value of the level tests is recorded (``modalinfo._stats._level_tests``), so the
level rule of before this branch (Bonferroni over the *judged* columns) is recomputed on
the same logs ("old"), beside the rule shipped (over the *tested* columns). The
binomial bound of a stated rate ``a`` over ``S`` logs is ``a S + 2 sqrt(a (1 - a) S)``.
Table: benchmarks/RESULTS.md, "left29-falarm".
"""

from __future__ import annotations

import math
import sys
import warnings

import numpy as np
from scipy.signal import lfilter

import modalinfo._stats as st
import modalinfo.telemetry.quality as qual

_calls: list = []
_tests: list = []
_orig_tests = st._level_tests
_orig_steps = st.level_steps
_orig_split = qual.spread_at_split


def _record_tests(x, p=st.INNOVATION_ORDER):
    out = _orig_tests(x, p)
    _tests.extend(out)
    return out


def _record_steps(x, alpha=st.LEVEL_ALPHA, skip=None):
    _tests.clear()
    res = _orig_steps(x, alpha, skip)
    p = [t.p_value for t in _tests if t.judged]
    _calls.append(("steps", len(_tests), p, alpha, res))
    return res


def _record_split(*args, **kwargs):
    res = _orig_split(*args, **kwargs)
    _calls.append(("split", res))
    return res


def ar1(rng: np.random.Generator, n: int, phi: float, m: int) -> np.ndarray:
    """``m`` independent stationary AR(1) columns of unit marginal variance."""
    e = rng.standard_normal((n + int(10 / (1 - phi)), m))
    return lfilter([math.sqrt(1 - phi * phi)], [1.0, -phi], e, axis=0)[-n:]


def main(phi: float, frames: int, seeds: int) -> None:
    st._level_tests = _record_tests
    st.level_steps = _record_steps  # variance_steps calls it
    qual.level_steps = _record_steps
    qual.spread_at_split = _record_split
    warnings.simplefilter("ignore")
    count = dict(level=0, old_level=0, variance=0, split=0, scale=0, block=0,
                 stationary_false=0, judged_level=0, judged_variance=0)
    for s in range(seeds):
        _calls.clear()
        r = qual.assess_quality(ar1(np.random.default_rng([29, s]), frames, phi, 10))
        level, variance = [c for c in _calls if c[0] == "steps"][:2]
        split = sum(len(c[1][0]) for c in _calls if c[0] == "split")
        count["level"] += bool(r.level_steps)
        count["old_level"] += bool(level[2]) and min(level[2]) < level[3] / len(level[2])
        count["variance"] += len(r.variance_steps) - split > 0
        count["split"] += split > 0
        count["scale"] += bool(r.scale_steps)
        limit = st.stationarity_threshold(r.effective_frames / st.STATIONARITY_BLOCKS)
        count["block"] += bool(math.isfinite(limit) and r.scale_ratio > limit)
        count["stationary_false"] += r.stationary is False
        count["judged_level"] += r.level_judged
        count["judged_variance"] += r.variance_judged
    print(f"| {phi} | {frames} x 10 | {seeds} | {count['judged_level'] / seeds:.1f} | "
          f"{count['old_level']} | {count['level']} | {count['judged_variance'] / seeds:.1f} | "
          f"{count['variance']} | {count['split']} | {count['scale']} | {count['block']} | "
          f"{count['stationary_false']} |", flush=True)


if __name__ == "__main__":
    main(float(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]) if len(sys.argv) > 3 else 200)
