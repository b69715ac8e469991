"""False alarms and detection of the level-stationarity rule (issue 27, left14-level).

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_level_left14.py {null|power} DRAWS

``null``: stationary AR(1) series (coefficient 0.5, 0.9, 0.99; unit marginal variance;
3000 frames of burn-in) of n = 500, 2000, 10^4 frames; the share of draws judged
(enough correlation times to tell a step from persistence) and of draws flagged by
:func:`modalinfo._stats.level_stationarity` at p < 5 % and 1 % (not judged counts as not
flagged), with the bound nominal + 2 binomial sd, ``a + 2 sqrt(a (1 - a) / DRAWS)``.
``power``: the same series plus a step of 1, 2, 3, 5 marginal sd at 40 % of the record,
or a ramp rising 1 or 3 marginal sd over it; each cell ``flagged at 1 % / judged``.
Seed 20261129. Table: benchmarks/RESULTS.md, rows "left14-level".
"""

from __future__ import annotations

import math
import sys

import numpy as np
from scipy.signal import lfilter

from modalinfo._stats import level_stationarity


def ar1(rng: np.random.Generator, n: int, rho: float) -> np.ndarray:
    """Stationary AR(1) of unit marginal variance (3000 frames of burn-in)."""
    e = rng.standard_normal(n + 3000)
    return lfilter([1.0], [1.0, -rho], e)[3000:] * math.sqrt(1.0 - rho * rho)


def main(what: str, draws: int) -> None:
    rng = np.random.default_rng(20261129)
    for rho in (0.5, 0.9, 0.99):
        for n in (500, 2000, 10000):
            if what == "null":
                ps = np.array([level_stationarity(ar1(rng, n, rho)).p_value
                               for _ in range(draws)])
                print(f"| null AR(1) {rho} | {n} | {draws} | {np.isfinite(ps).mean():.3f} | "
                      f"{np.mean(ps < .05):.3f} ({0.05 + 2 * math.sqrt(.0475 / draws):.3f}) | "
                      f"{np.mean(ps < .01):.3f} ({0.01 + 2 * math.sqrt(.0099 / draws):.3f}) |",
                      flush=True)
                continue
            row = []
            for kind, size in (("step", 1), ("step", 2), ("step", 3), ("step", 5),
                               ("ramp", 1), ("ramp", 3)):
                ps = []
                for _ in range(draws):
                    x = ar1(rng, n, rho)
                    if kind == "step":
                        x[int(0.4 * n):] += size
                    else:
                        x += size * np.linspace(-0.5, 0.5, n)
                    ps.append(level_stationarity(x).p_value)
                ps = np.array(ps)
                row.append(f"{np.mean(ps < .01):.2f}/{np.isfinite(ps).mean():.2f}")
            print(f"| power AR(1) {rho} | {n} | {draws} | " + " | ".join(row) + " |", flush=True)


if __name__ == "__main__":
    main(sys.argv[1], int(sys.argv[2]))
