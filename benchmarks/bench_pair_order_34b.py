"""False alarms and power of the pair-order and copied-block rules (issue 27, fix34-b).

``modalinfo.telemetry.assess_quality`` reports frames written in swapped pairs
(``QualityReport.pair_order``) and frames equal to an earlier frame
(``QualityReport.copied_frames``). Measured here on the clean log families the layout
rule was calibrated on (``benchmarks/_common.clean_logs``, as in bench_layout_left31.py:
stationary AR(1) logs, Noll-like spreads, one ``rho`` for every mode, rho 0.999, rho
-0.5, white), ``kaos_like`` open- and closed-loop logs and the shipped logs, each
judged as generated (a false alarm when either rule fires) and with every pair of frames
swapped (power of the pair-order rule); and AR(1) logs rounded to 0.1 / 0.01 / 0.001 of
their sigma, whose frames agree by chance (false alarms of the copied-block rule).

Run: ``PYTHONPATH=$PWD python benchmarks/bench_pair_order_34b.py [--logs 35]``.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import ar_log, clean_logs  # noqa: E402

from modalinfo.telemetry import assess_quality  # noqa: E402

SHAPES = [(2000, 20), (4000, 27), (8000, 50)]


def swapped(x: np.ndarray) -> np.ndarray:
    """Every pair of frames (2k, 2k + 1) written in reverse order."""
    y = x.copy()
    k = (len(x) // 2) * 2
    y[0:k:2], y[1:k:2] = x[1:k:2], x[0:k:2]
    return y


def judge(x: np.ndarray) -> tuple[bool, bool, bool, float]:
    """(pair-order false alarm, copies false alarm, swapped found, swapped p value)."""
    clean = assess_quality(x)
    sw = assess_quality(swapped(x))
    p = sw.pair_order[2] if sw.pair_order else float("nan")
    return bool(clean.pair_order), bool(clean.copied_frames.size), bool(sw.pair_order), p


def main(argv: list[str] | None = None) -> int:
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--logs", type=int, default=35, help="logs per shape and family")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(34)
    t0 = time.process_time()
    totals = np.zeros(4, dtype=int)
    print(f"{'family':<22} {'shape':>12} {'pair FA':>8} {'copy FA':>8} "
          f"{'swapped found':>14} {'largest p':>10}")

    def row(name: str, shape: tuple, results: list) -> None:
        fa_p = sum(r[0] for r in results)
        fa_c = sum(r[1] for r in results)
        found = sum(r[2] for r in results)
        worst = max((r[3] for r in results if r[2]), default=float("nan"))
        totals[:] += (fa_p, fa_c, found, len(results))
        print(f"{name:<22} {shape[0]:>6}x{shape[1]:<5} {fa_p:>3}/{len(results):<4} "
              f"{fa_c:>3}/{len(results):<4} {found:>8}/{len(results):<5} {worst:>10.2g}",
              flush=True)

    for name, shape, logs in clean_logs(SHAPES, args.logs, rng):
        row(name, shape, [judge(x) for x in logs])
    fa_p, fa_c, found, total = totals
    print(f"pair-order false alarms {fa_p} of {total} clean logs, copied-block false alarms "
          f"{fa_c} of {total}; swapped logs found {found} of {total}")
    # rounded logs: frames agree by chance, no block was copied
    fa = n = 0
    for q in (0.1, 0.01, 0.001):
        for m in (1, 2, 3, 5):
            for _ in range(10):
                x = ar_log((8000, m), np.full(m, rng.uniform(0.9, 0.999)), np.ones(m), rng)
                fa += bool(assess_quality(np.round(x / q) * q).copied_frames.size)
                n += 1
    print(f"copied-block false alarms on rounded logs (0.1 / 0.01 / 0.001 sigma, 1-5 modes, "
          f"rho 0.9-0.999): {fa} of {n}; CPU {time.process_time() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
