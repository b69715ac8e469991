"""False alarms and power of the spread (variance-step) rule (issue 27, left18-quality).

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_variance_left18.py {null|synth|power} DRAWS

``null``: stationary logs of Gaussian white noise and of AR(1) 0.95 columns (unit
marginal variance, 3000 frames of burn-in), 200 / 1000 / 4000 frames x 20 / 200 columns;
per cell the mean number of columns judged and the logs with any column flagged by
:func:`modalinfo._stats.variance_steps` (family-wise 1 %, as ``assess_quality`` runs it
on a log of <= 65,536 frames), with the one-sided binomial p-value of that count at
1 % (``scipy.stats.binom.sf``; below 0.05 would say the rate is exceeded).
``synth``: ``kaos_like`` closed- and open-loop logs (27 modes) of 1000 and 4000 frames
through :func:`modalinfo.telemetry.assess_quality`: logs with ``variance_steps``.
``power``: the l11 input of round 18 PART a (``kaos_like(2000, seed=s)`` then the same
log with its columns reversed, stacked; seeds 0..DRAWS-1), and a step of the standard
deviation by x1.3 / 1.5 / 2 at mid-record in one column of 50 (white and AR(1) 0.95) at
1000 and 4000 frames, through ``assess_quality``: logs whose ``variance_steps`` name the
stepped column (l11: any column), and the median frame found.
Seed 20261130. Table: benchmarks/RESULTS.md, "left18-quality".
"""

from __future__ import annotations

import math
import sys

import numpy as np
from scipy.signal import lfilter
from scipy.stats import binom

from modalinfo._stats import variance_steps
from modalinfo.telemetry import assess_quality
from modalinfo.telemetry.synthetic.presets import kaos_like


def columns(rng: np.random.Generator, n: int, m: int, rho: float) -> np.ndarray:
    """``m`` stationary AR(1) columns of unit marginal variance (rho 0: white)."""
    if rho == 0.0:
        return rng.standard_normal((n, m))
    e = rng.standard_normal((n + 3000, m))
    return lfilter([1.0], [1.0, -rho], e, axis=0)[3000:] * math.sqrt(1.0 - rho * rho)


def null(draws: int) -> None:
    rng = np.random.default_rng(20261130)
    print("| kind | frames | columns | logs | mean judged | logs flagged | binomial p |")
    for rho, kind in ((0.0, "white"), (0.95, "AR(1) 0.95")):
        for n in (200, 1000, 4000):
            for m in (20, 200):
                hits, judged = 0, 0
                for _ in range(draws):
                    flagged, j = variance_steps(columns(rng, n, m, rho))
                    hits += bool(flagged)
                    judged += j
                print(f"| {kind} | {n} | {m} | {draws} | {judged / draws:.1f} | {hits} | "
                      f"{binom.sf(hits - 1, draws, 0.01):.2f} |", flush=True)


def synth(draws: int) -> None:
    print("| kaos_like | frames | logs | mean judged | logs flagged | binomial p |")
    for closed in (True, False):
        for n in (1000, 4000):
            hits, judged = 0, 0
            for seed in range(draws):
                rep = assess_quality(kaos_like(n, closed_loop=closed, seed=1000 + seed))
                hits += bool(rep.variance_steps)
                judged += rep.variance_judged
            print(f"| {'closed' if closed else 'open'} | {n} | {draws} | "
                  f"{judged / draws:.1f} | {hits} | {binom.sf(hits - 1, draws, 0.01):.2f} |",
                  flush=True)


def power(draws: int) -> None:
    hits, found = 0, []
    for seed in range(draws):
        k = kaos_like(2000, seed=seed).coeffs
        rep = assess_quality(np.vstack([k, k[:, ::-1]]))
        hits += bool(rep.variance_steps)
        found.append(len(rep.variance_steps))
    print(f"| l11 (kaos_like 2000 + reversed) | {draws} | {hits} | "
          f"median {np.median(found):.0f} of 27 modes |", flush=True)
    rng = np.random.default_rng(20261130)
    for rho, kind in ((0.0, "white"), (0.95, "AR(1) 0.95")):
        for n in (1000, 4000):
            for factor in (1.3, 1.5, 2.0):
                hits, frames = 0, []
                for _ in range(draws):
                    x = columns(rng, n, 50, rho)
                    x[n // 2:, 7] *= factor
                    rep = assess_quality(x)
                    named = [f for label, f, _, _ in rep.variance_steps if label == "col7"]
                    hits += bool(named)
                    frames += named
                where = f"{np.median(frames):.0f}" if frames else "-"
                print(f"| {kind}, x{factor} in 1 of 50 | {n} | {draws} | {hits} | {where} |",
                      flush=True)


if __name__ == "__main__":
    {"null": null, "synth": synth, "power": power}[sys.argv[1]](int(sys.argv[2]))
