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

import sys
import time

import numpy as np
from _common import clean_logs

from modalinfo.telemetry.checks import LAYOUT_ALPHA, layout_lag1

SHAPES = [(2000, 20), (4000, 27), (8000, 50), (20000, 200), (300, 200), (250, 200),
          (1500, 1000)]


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

    for name, shape, logs in clean_logs(SHAPES, args.logs, rng):
        row(name, shape, [judge(x) for x in logs])
    # 95 % upper bound on the rate with no false alarm in `total` logs: 3 / total
    print(f"false alarms {total_fa} of {total} logs (largest margin {worst:.2f}; 95 % upper "
          "bound "
          f"{3.0 / total if total_fa == 0 else float('nan'):.2g}); "
          f"CPU {time.process_time() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
