"""DM test size and the persistent-volatility rule (issue 27, fix46-a, fix47-c; round 46 P39-P43).

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_dm_volatility_46a.py DRAWS [evaluate]

Loss differentials d of N = 500 and 2000 origins fed to ``_dm_test`` (the p-value
``evaluate`` reports) and to ``_volatility_z`` (its persistent-volatility rule, flagged
above ``_DM_VOL_Z`` in absolute value) with a level at each origin: ``mds phi`` is
``x_t e_(t+1)`` for an AR(1) ``x`` of coefficient phi (two forecasts equal in MSE,
``(2 phi - 1) x_t`` against persistence), level ``x_t^2``; ``gauss phi`` a Gaussian AR(1)
differential ``y_t``, level ``y_(t-1)^2`` (for phi = 0: an independent AR(1) 0.99 mode's
square, so that the rule's gate on the level's persistence passes); ``t3 phi`` the same
with t3 innovations; ``resonance`` a Gaussian AR(2) (1.9, -0.95), level its lagged
square; ``product`` ``e_t e_(t+1)`` of white noise, level ``e_t^2`` (not persistent: the
gate). Columns: rejections at 5 % and 1 % (nominal; binomial sd ``sqrt(a (1 - a) /
DRAWS)``), the share flagged, and the rejections that still count for a flagged pair (p
below 5 % / ``_DM_VOL_FACTOR``; unflagged pairs at 5 %). Seed 20261201.

``evaluate``: through :func:`modalinfo.forecast.evaluate` (one predictor, h = 1, train 0.5,
seeds 9000 + k as in round 46's scripts): P43 (phi 0.9, 500 origins), P39 (0.9, 2000), P40
(0.99, 2000), phi 0.7 / 0.8 (500) with ``(2 phi - 1) x_t`` (equal MSE); power: ``phi x_t``
(DRAWS / 3 draws); forecasts that differ in population: ``0.2 x_t`` on white noise (worse
than the mean), ``0.3 x_t`` on AR(1) 0.5 (better than both baselines). Columns: raw p < 5 %,
``beats_baseline`` (the flagged-pair rule included), the share flagged.
Tables: benchmarks/RESULTS.md, rows "fix46-a" (the rule before fix47-c) and "fix47-c".
"""

from __future__ import annotations

import math
import sys
import warnings

import numpy as np
from scipy.signal import lfilter

import modalinfo.forecast.evaluate  # noqa: F401  (the module, not the function)
from modalinfo.forecast import LinearPredictor, evaluate
from modalinfo.forecast.evaluate import _DM_VOL_FACTOR, _DM_VOL_Z, _dm_test, _volatility_z

EV = sys.modules["modalinfo.forecast.evaluate"]


def draw(rng: np.random.Generator, kind: str, phi: float, n: int
         ) -> tuple[np.ndarray, np.ndarray]:
    """One loss differential of ``n`` origins and its level (1000 frames of burn-in)."""
    if kind == "mds":
        e = rng.standard_normal(n + 1001)
        x = lfilter([1.0], [1.0, -phi], e)[1000:]
        return x[:-1] * e[1001:], x[:-1] ** 2
    if kind == "product":  # e_t e_(t+1): a fitted forecast of white noise against its mean
        e = rng.standard_normal(n + 1)
        return e[:-1] * e[1:], e[:-1] ** 2
    if kind == "resonance":  # AR(2) (1.9, -0.95): a sharp resonance
        y = lfilter([1.0], [1.0, -1.9, 0.95], rng.standard_normal(n + 1001))[1000:]
        return y[1:], y[:-1] ** 2
    e = rng.standard_normal(n + 1001) if kind == "gauss" else rng.standard_t(3, n + 1001)
    y = lfilter([1.0], [1.0, -phi], e)[1000:]
    if phi > 0.0:
        return y[1:], y[:-1] ** 2
    other = lfilter([1.0], [1.0, -0.99], rng.standard_normal(n + 1000))[1000:]
    return y[1:], other**2


def main(draws: int) -> None:
    rng = np.random.default_rng(20261201)
    print("| d | N | draws | rej 5 % | rej 1 % | flagged | counted rej 5 % |")
    print("|---|---|---|---|---|---|---|")
    for kind, phi in (("mds", 0.9), ("mds", 0.99), ("gauss", 0.0), ("gauss", 0.9),
                      ("gauss", 0.99), ("t3", 0.0), ("t3", 0.9), ("resonance", 0.0),
                      ("product", 0.0)):
        for n in (500, 2000):
            p = np.empty(draws)
            flag = np.empty(draws, dtype=bool)
            for k in range(draws):
                d, level = draw(rng, kind, phi, n)
                p[k] = _dm_test(d, 1)[1]
                flag[k] = abs(_volatility_z(d, level)) > _DM_VOL_Z
            p = np.nan_to_num(p, nan=1.0)
            counted = np.where(flag, p < 0.05 / _DM_VOL_FACTOR, p < 0.05)
            print(f"| {kind} {phi} | {n} | {draws} | {np.mean(p < .05):.3f} | "
                  f"{np.mean(p < .01):.3f} | {flag.mean():.3f} | {counted.mean():.3f} |",
                  flush=True)
    print(f"(2 binomial sd at 5 %: {2 * math.sqrt(.0475 / draws):.3f})")


def through_evaluate(draws: int) -> None:
    seen = []
    rule = EV._volatility_z

    def spy(d, level):
        seen.append(rule(d, level))
        return seen[-1]

    EV._volatility_z = spy
    print("| case | phi | origins | a | draws | raw 5 % | beats | flagged |")
    print("|---|---|---|---|---|---|---|---|")
    for case, phi, frames, a, reps in (
            ("P43", 0.9, 1000, 0.8, draws), ("P39", 0.9, 4000, 0.8, draws),
            ("P40", 0.99, 4000, 0.98, draws), ("equal", 0.7, 1000, 0.4, draws),
            ("equal", 0.8, 1000, 0.6, draws), ("power", 0.95, 2000, 0.95, draws // 3),
            ("power", 0.99, 4000, 0.99, draws // 3), ("white", 0.0, 1000, 0.2, draws),
            ("better", 0.5, 1000, 0.3, draws)):
        rows = []
        for k in range(max(1, reps)):
            e = np.random.default_rng(9000 + k).normal(size=frames + 1000)
            x = lfilter([1.0], [1.0, -phi], e)[1000:]
            seen.clear()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = evaluate({"c": LinearPredictor(a=a, b=0.0)}, x, train=0.5, horizons=[1])
            flagged = bool(seen) and abs(seen[0]) > _DM_VOL_Z
            rows.append((r.pvalue[2, 0], r.beats_baseline[2, 0], flagged))
        m = np.nan_to_num(np.array(rows, dtype=float), nan=1.0)
        print(f"| {case} | {phi} | {frames // 2} | {a:g} | {len(rows)} | "
              f"{np.mean(m[:, 0] < .05):.3f} | {m[:, 1].mean():.3f} | {m[:, 2].mean():.3f} |",
              flush=True)
    EV._volatility_z = rule


if __name__ == "__main__":
    if sys.argv[2:] == ["evaluate"]:
        through_evaluate(int(sys.argv[1]))
    else:
        main(int(sys.argv[1]) if len(sys.argv) > 1 else 300)
