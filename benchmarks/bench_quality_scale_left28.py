"""The quality pass at the 4-m scale: wall time (median of 3) and tracemalloc peak.

Issue 27, left28-quality (adversarial round 27 PART b, S01: ``modalinfo info`` of a
10^4 x 2000-mode log spent 96 % of 97 s in the quality pass). The log: a seeded AR(1)
series (rho 0.9, unit innovations) of ``--frames`` x ``--modes``, float64 in memory.

Usage::

    PYTHONPATH=$PWD OPENBLAS_NUM_THREADS=1 python benchmarks/bench_quality_scale_left28.py \\
        --modes 200 2000 --repeats 3
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
import tracemalloc

from _common import ar1_log

from modalinfo.telemetry import assess_quality


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=10_000)
    parser.add_argument("--modes", type=int, nargs="+", default=[200, 2000])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    assess_quality(ar1_log(500, 3, 27))  # compile the numba kernel outside the timings
    for m in args.modes:
        x = ar1_log(args.frames, m, 27)
        walls = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            report = assess_quality(x)
            walls.append(time.perf_counter() - t0)
        tracemalloc.start()
        assess_quality(x)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        print(f"{args.frames} x {m}: median {statistics.median(walls):.2f} s of "
              f"{', '.join(f'{w:.2f}' for w in walls)}; tracemalloc peak {peak / 2**20:.0f} "
              f"MiB (data {x.nbytes / 2**20:.0f} MiB); flagged {report.n_flagged}, "
              f"load {os.getloadavg()[0]:.1f}", flush=True)


if __name__ == "__main__":
    main()
