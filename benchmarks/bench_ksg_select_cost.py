"""Benchmark: ``select_inputs``' KSG cost model against the CPU of the search it refuses.

An independent series (the search stops after its first step, which the model counts:
``m (1 + N)`` KSG CMI estimates of 2 columns) of n rows, 2 candidates (one series, 2
lags), N = 19 surrogates. Printed per n: the model before round 12 (1.25e-6 n log2(n)
per estimate, written out here), the package's ``first_step_seconds``, the measured CPU
of ``select_inputs`` (``time.process_time``, one BLAS thread, median of ``--repeats``)
and measured / model for both (within 0.67-1.5: the target of Leftovers 12-cost).

Run::

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. python benchmarks/bench_ksg_select_cost.py
"""

from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1000, 3000, 10_000])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    from modalinfo.information.selection import first_step_seconds, select_inputs

    print(f"# load {os.getloadavg()[0]:.1f}")
    print(f"{'n':>7s}{'calls':>7s}{'before s':>10s}{'after s':>10s}{'measured':>10s}"
          f"{'m/before':>10s}{'m/after':>9s}")
    for n_rows in args.sizes:
        data = np.random.default_rng(n_rows).standard_normal((n_rows + 2, 1))
        n, m, s = n_rows, 2, 19
        select_inputs(data[:200], target=0, max_lag=2, method="ksg", n_surrogates=s,
                      intervals=False)  # imports and first calls, not timed
        spent = []
        for _ in range(args.repeats):
            start = time.process_time()
            res = select_inputs(data, target=0, max_lag=2, method="ksg", n_surrogates=s,
                                intervals=False)
            spent.append(time.process_time() - start)
        if len(res.inputs):
            print(f"# n = {n}: the search took a step beyond the first; not comparable")
            continue
        measured = float(np.median(spent))
        before = m * (1 + s) * 1.25e-6 * n * math.log2(n)
        after = first_step_seconds("ksg", n, m, s)
        print(f"{n:7d}{m * (1 + s):7d}{before:10.3f}{after:10.3f}{measured:10.3f}"
              f"{measured / before:10.2f}{measured / after:9.2f}")
    print(f"# load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
