"""DM test size and the persistent-volatility rule (issue 27, fix46-a; round 46 PART a P39-P43).

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_dm_volatility_46a.py DRAWS

Loss differentials d of N = 500 and 2000 origins fed to ``_dm_test`` (the p-value
``evaluate`` reports) and to ``_volatility_z`` (its persistent-volatility rule, flagged
above ``_DM_VOL_Z``): ``mds phi`` is ``x_t e_(t+1)`` for an AR(1) ``x`` of coefficient phi
(two forecasts equal in MSE, ``(2 phi - 1) x_t`` against persistence); ``gauss phi`` a
Gaussian AR(1) differential (white for phi = 0); ``t3 phi`` the same with t3 innovations;
``resonance`` a Gaussian AR(2) (1.9, -0.95); ``product`` ``e_t e_(t+1)`` of white noise.
Columns: rejections at 5 % and 1 % (nominal; binomial sd ``sqrt(a (1 - a) / DRAWS)``),
the share flagged, and the rejections that still count for a flagged pair (p below
5 % / ``_DM_VOL_FACTOR``; unflagged pairs at 5 %). Seed 20261201. Table:
benchmarks/RESULTS.md, rows "fix46-a".
"""

from __future__ import annotations

import math
import sys

import numpy as np
from scipy.signal import lfilter

from modalinfo.forecast.evaluate import _DM_VOL_FACTOR, _DM_VOL_Z, _dm_test, _volatility_z


def draw(rng: np.random.Generator, kind: str, phi: float, n: int) -> np.ndarray:
    """One loss differential of ``n`` origins (1000 frames of burn-in)."""
    if kind == "mds":
        e = rng.standard_normal(n + 1001)
        x = lfilter([1.0], [1.0, -phi], e)[1000:]
        return x[:-1] * e[1001:]
    if kind == "resonance":  # AR(2) (1.9, -0.95): a sharp resonance
        return lfilter([1.0], [1.0, -1.9, 0.95], rng.standard_normal(n + 1000))[1000:]
    if kind == "product":  # e_t e_(t+1): a fitted forecast of white noise against its mean
        e = rng.standard_normal(n + 1)
        return e[:-1] * e[1:]
    e = rng.standard_normal(n + 1000) if kind == "gauss" else rng.standard_t(3, n + 1000)
    return lfilter([1.0], [1.0, -phi], e)[1000:]


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
                d = draw(rng, kind, phi, n)
                p[k] = _dm_test(d, 1)[1]
                flag[k] = _volatility_z(d, 1) > _DM_VOL_Z
            p = np.nan_to_num(p, nan=1.0)
            counted = np.where(flag, p < 0.05 / _DM_VOL_FACTOR, p < 0.05)
            print(f"| {kind} {phi} | {n} | {draws} | {np.mean(p < .05):.3f} | "
                  f"{np.mean(p < .01):.3f} | {flag.mean():.3f} | {counted.mean():.3f} |",
                  flush=True)
    print(f"(2 binomial sd at 5 %: {2 * math.sqrt(.0475 / draws):.3f})")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 300)
