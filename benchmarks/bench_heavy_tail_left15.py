"""False-alarm rate of the bootstrap's heavy-tail rule on Gaussian series (issue 27, left15).

The rule (``modalinfo.information.resampling._heavy_tail_rule``) flags a pair when the
largest ``|e - median(e)| / (1.4826 MAD(e))`` of the AR(4) innovations ``e`` of either
series passes a threshold ``k(n)``. This script computes that statistic for many seeded
Gaussian series at once (the AR(4) least squares with a constant through batched normal
equations, the same residuals as ``modalinfo._stats.ar_innovations``), and reports, for
the threshold the rule used before left15 ("before"), the left15 one (the spread of a
value outside its sample, "left15") and the one it uses now (inside, left18: "after"),
the share of series and of
pairs (two independent series) above it, with the exact binomial (Clopper-Pearson) 95 %
range. One column per series, so a pair's rate is ``1 - (1 - p)^2`` for independent
series and at most ``2 p`` (union bound) for dependent ones.

    python benchmarks/bench_heavy_tail_left15.py [--series 200000] [--n 500 2000 10000]
"""
from __future__ import annotations

import argparse
import time

import numpy as np
from scipy import signal, stats

from modalinfo._stats import INNOVATION_ORDER
from modalinfo.telemetry.quality import MAD_TO_SIGMA, gaussian_threshold


def innovations(x: np.ndarray, p: int = INNOVATION_ORDER) -> np.ndarray:
    """AR(p) least-squares residuals with a constant of each row of x, shape (m, n - p)."""
    m, n = x.shape
    lags = np.stack([x[:, p - i:n - i] for i in range(1, p + 1)] + [np.ones((m, n - p))],
                    axis=2)
    target = x[:, p:]
    gram = np.einsum("mti,mtj->mij", lags, lags)
    rhs = np.einsum("mti,mt->mi", lags, target)
    coef = np.linalg.solve(gram, rhs[..., None])[..., 0]
    return target - np.einsum("mti,mi->mt", lags, coef)


def statistic(e: np.ndarray) -> np.ndarray:
    """The rule's ``max |e - median| / (1.4826 MAD)`` of each row."""
    dev = np.abs(e - np.median(e, axis=1, keepdims=True))
    return dev.max(axis=1) / (MAD_TO_SIGMA * np.median(dev, axis=1))


def draw(rng: np.random.Generator, m: int, n: int, phi: float) -> np.ndarray:
    """m unit-innovation Gaussian AR(1) series of n samples (phi = 0: white)."""
    g = rng.standard_normal((m, n + (200 if phi else 0)))
    if phi:
        g = signal.lfilter([1.0], [1.0, -phi], g, axis=1)[:, 200:]
    return g


def clopper(k: int, m: int) -> tuple[float, float]:
    lo = stats.beta.ppf(0.025, k, m - k + 1) if k else 0.0
    hi = stats.beta.ppf(0.975, k + 1, m - k) if k < m else 1.0
    return float(lo), float(hi)


def left15_threshold(t: int, n_series: int = 2, alpha: float = 1e-4) -> float:
    """The left15 threshold: the spread of a value *outside* its sample (left18 fixed it)."""
    from modalinfo._stats import MAD_RELATIVE_SD, mad_union_threshold
    nodes, weights = np.polynomial.hermite_e.hermegauss(80)
    s = 1.0 + (MAD_RELATIVE_SD / np.sqrt(t)) * nodes
    keep = s > 0.0
    w = weights[keep] / weights[keep].sum()
    return mad_union_threshold(s[keep], w, t, n_series, t, alpha, 1.0, 20.0,
                               in_sample=False)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--series", type=int, default=200_000)
    ap.add_argument("--n", type=int, nargs="+", default=[500, 2000, 10000])
    ap.add_argument("--phi", type=float, nargs="+", default=[0.0, 0.9])
    ap.add_argument("--seed", type=int, default=20261129)
    args = ap.parse_args()
    from modalinfo.information.resampling import heavy_tail_threshold
    for n in args.n:
        old = gaussian_threshold(n - INNOVATION_ORDER, 1e-4)
        new = heavy_tail_threshold(n - INNOVATION_ORDER)
        left15 = left15_threshold(n - INNOVATION_ORDER)
        for phi in args.phi:
            rng = np.random.default_rng([args.seed, n, int(phi * 1000)])
            chunk = max(1, min(args.series, 4_000_000 // n))
            zs = []
            t0 = time.process_time()
            done = 0
            while done < args.series:
                m = min(chunk, args.series - done)
                zs.append(statistic(innovations(draw(rng, m, n, phi))))
                done += m
            z = np.concatenate(zs)
            pairs = z[: z.size // 2 * 2].reshape(-1, 2).max(axis=1)
            for label, k in (("before", old), ("left15", left15), ("after", new)):
                hit = int((pairs > k).sum())
                lo, hi = clopper(hit, pairs.size)
                print(f"n={n:6d} phi={phi:4.2f} {label:6s} k={k:.3f}: series "
                      f"{int((z > k).sum())}/{z.size}, pairs {hit}/{pairs.size} = "
                      f"{hit / pairs.size:.2e} (95 % {lo:.1e}-{hi:.1e})", flush=True)
            print(f"   quantiles of pair max z: 0.999 {np.quantile(pairs, 0.999):.3f} "
                  f"0.9999 {np.quantile(pairs, 0.9999):.3f}; "
                  f"{time.process_time() - t0:.0f} s CPU", flush=True)


if __name__ == "__main__":
    main()
