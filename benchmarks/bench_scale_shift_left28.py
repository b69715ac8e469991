"""The forecasts' train / test scale shift at the 4-m scale: wall time and peak, before / after.

Issue 27, left28-misc: ``modalinfo.forecast.evaluate._scale_shift`` fitted its per-mode
AR(4) with a constant by one ``numpy.linalg.lstsq`` per mode; it now shares the quality
pass's stacked solve (``modalinfo._stats.stacked_ar_fits``). The log: a seeded AR(1)
series (rho 0.9, unit innovations) of ``--frames`` x ``--modes``, float64 in memory,
half of it training. Wall and CPU time (``time.process_time``, less sensitive to a
shared machine's load): medians of ``--repeats``; tracemalloc peak of one more run.
With ``--before TREE`` the same measurement runs in a child process on the source
tree ``TREE`` (e.g. ``git archive <commit> | tar -x -C TREE``), the two sets of ratios
are compared and the speed-up printed.

Usage::

    PYTHONPATH=$PWD OPENBLAS_NUM_THREADS=1 python benchmarks/bench_scale_shift_left28.py \\
        --frames 10000 --modes 2000 --repeats 3 --before /tmp/old
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
import tracemalloc

import numpy as np
from _common import ar1_log


def measure(frames: int, modes: int, repeats: int) -> dict:
    """Median wall time [s], tracemalloc peak [MiB] and the ratios of ``_scale_shift``."""
    from modalinfo.forecast.evaluate import _scale_shift

    x = ar1_log(frames, modes, 28)
    n_train = frames // 2
    walls, cpus = [], []
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        ratio = _scale_shift(x, x[:n_train], n_train, 1000, 0.01)[0]
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    tracemalloc.start()
    _scale_shift(x, x[:n_train], n_train, 1000, 0.01)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return {"wall": statistics.median(walls), "walls": walls, "cpu": statistics.median(cpus),
            "peak": peak / 2**20,
            "ratio": ratio.tolist(), "load": os.getloadavg()[0]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=10_000)
    parser.add_argument("--modes", type=int, default=2000)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--before", help="source tree of the code before, timed alike")
    parser.add_argument("--json", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    now = measure(args.frames, args.modes, args.repeats)
    if args.json:
        print(json.dumps(now))
        return
    print(f"{args.frames} x {args.modes}: median {now['wall']:.2f} s of "
          f"{', '.join(f'{w:.2f}' for w in now['walls'])} (CPU {now['cpu']:.2f} s); "
          f"tracemalloc peak {now['peak']:.0f} MiB; load {now['load']:.1f}", flush=True)
    if args.before:
        env = dict(os.environ, PYTHONPATH=os.path.abspath(args.before))
        out = subprocess.run(
            [sys.executable, os.path.abspath(__file__), "--frames", str(args.frames),
             "--modes", str(args.modes), "--repeats", str(args.repeats), "--json"],
            env=env, capture_output=True, text=True, check=True, cwd=args.before)
        before = json.loads(out.stdout.splitlines()[-1])
        a, b = np.array(before["ratio"]), np.array(now["ratio"])
        same = np.isnan(a) == np.isnan(b)
        rel = float(np.nanmax(np.abs(b / a - 1.0))) if np.isfinite(a).any() else 0.0
        print(f"before: median {before['wall']:.2f} s of "
              f"{', '.join(f'{w:.2f}' for w in before['walls'])} (CPU {before['cpu']:.2f} s); "
              "tracemalloc peak "
              f"{before['peak']:.0f} MiB; load {before['load']:.1f}")
        print(f"speed-up x{before['wall'] / now['wall']:.2f} wall, "
              f"x{before['cpu'] / now['cpu']:.2f} CPU; modes judged alike: "
              f"{bool(same.all())}; largest relative change of a ratio {rel:.1e}")


if __name__ == "__main__":
    main()
