"""False alarms and power of the content rule on a log's layout (issue 27, left31-orient).

``modalinfo.telemetry.checks.layout_doubt`` judges whether an array read as (frames,
modes) looks stored (modes, frames). Measured here, each log judged as stored (a false
alarm when flagged) and transposed (power when flagged):

- seeded stationary AR(1) logs of the shapes the package sees (2,000 x 20 to 20,000 x
  200), each mode's coefficient ``rho0 ** (n + 1)`` (``n`` its Noll radial order,
  ``rho0`` uniform in 0.5-0.999: low orders decorrelate slowest) and its standard
  deviation ``(n + 1) ** (-11 / 6)`` (Noll-like, falling with mode order);
- the same with one ``rho`` for every mode, 0.5 to 0.999, -0.5 (a closed loop's
  overshoot), and white logs (rho 0);
- near-square shapes (300 x 200 as in round 31 PART b a25, 250 x 200, 1,500 x 1,000);
- ``kaos_like`` open- and closed-loop logs and the shipped logs of data/.

Run: ``PYTHONPATH=$PWD python benchmarks/bench_layout_left31.py [--logs 20]``.
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np
from scipy.signal import lfilter

from modalinfo.telemetry.checks import LAYOUT_ALPHA, layout_lag1

SHAPES = [(2000, 20), (4000, 27), (8000, 50), (20000, 200), (300, 200), (250, 200),
          (1500, 1000)]


def radial_orders(m: int) -> np.ndarray:
    """Noll radial order of modes Z2.. (m of them)."""
    j = np.arange(2, m + 2)
    return np.floor((np.sqrt(8 * j - 7) - 1) / 2).astype(int)


def ar_log(shape: tuple[int, int], rhos: np.ndarray, sd: np.ndarray,
           rng: np.random.Generator) -> np.ndarray:
    """Stationary AR(1) columns (each started from its stationary law)."""
    t, m = shape
    e = rng.standard_normal((t, m))
    x = np.empty((t, m))
    for k in range(m):
        r = float(rhos[k])
        z = e[:, k] * math.sqrt(1 - r * r)
        z[0] = e[0, k]
        x[:, k] = lfilter([1.0], [1.0, -r], z)
    return x * sd


def rhos(family: str, m: int, rng: np.random.Generator) -> np.ndarray:
    """Each mode's AR(1) coefficient in one log of ``family``."""
    if family == "noll rho0 .5-.999":
        return rng.uniform(0.5, 0.999) ** (radial_orders(m) + 1.0)
    if family == "one rho .5-.999":
        return np.full(m, rng.uniform(0.5, 0.999))
    if family == "rho -0.5":
        return np.full(m, -0.5)
    return np.full(m, 0.999 if family == "rho 0.999" else 0.0)


FAMILIES = ("noll rho0 .5-.999", "one rho .5-.999", "rho 0.999", "rho -0.5", "white")


def margin(x: np.ndarray) -> float:
    """``(m1 - max(m0, 0)) / threshold``: flagged above 1."""
    m0, m1, threshold = layout_lag1(x)
    return (m1 - max(m0, 0.0)) / threshold


def judge(x: np.ndarray) -> tuple[float, float]:
    """Margins as stored (a false alarm above 1) and transposed (found above 1)."""
    return margin(x), margin(np.ascontiguousarray(x.T))


def main(argv: list[str] | None = None) -> int:
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--logs", type=int, default=20, help="logs per shape and family")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(31)
    t0 = time.process_time()
    total_fa = total = 0
    worst = -np.inf
    print(f"LAYOUT_ALPHA {LAYOUT_ALPHA:g}; logs per cell {args.logs}; margin = "
          "(m1 - max(m0, 0)) / threshold, flagged above 1")
    print(f"{'family':<22} {'shape':>12} {'false alarms':>13} {'max margin':>10} "
          f"{'power (transposed)':>19} {'min margin':>10}")

    def row(name: str, shape: tuple, margins: list) -> None:
        nonlocal total_fa, total, worst
        kept = np.array([a for a, _ in margins])
        flipped = np.array([b for _, b in margins])
        fa, k = int((kept > 1).sum()), len(margins)
        total_fa += fa
        total += k
        worst = max(worst, float(kept.max()))
        print(f"{name:<22} {shape[0]:>6}x{shape[1]:<5} {fa:>6}/{k:<6} {kept.max():>10.2f} "
              f"{int((flipped > 1).sum()):>10}/{k:<8} {flipped.min():>10.2f}")

    for shape in SHAPES:
        sd = (radial_orders(shape[1]) + 1.0) ** (-11.0 / 6.0)
        for family in FAMILIES:
            row(family, shape, [judge(ar_log(shape, rhos(family, shape[1], rng), sd, rng))
                                for _ in range(args.logs)])
    from modalinfo.io import load
    from modalinfo.telemetry.synthetic import kaos_like

    for closed in (False, True):
        row("kaos_like " + ("closed" if closed else "open"), (4000, 27),
            [judge(kaos_like(4000, closed_loop=closed, seed=seed).coeffs)
             for seed in range(5)])
    root = Path(__file__).resolve().parent.parent / "data"
    for path in sorted(root.glob("*.npz")):
        coeffs = np.asarray(load(path).coeffs)
        row(path.name, coeffs.shape, [judge(coeffs)])
    # 95 % upper bound on the rate with no false alarm in `total` logs: 3 / total
    print(f"false alarms {total_fa} of {total} logs (largest margin {worst:.2f}; 95 % upper "
          "bound "
          f"{3.0 / total if total_fa == 0 else float('nan'):.2g}); "
          f"CPU {time.process_time() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
