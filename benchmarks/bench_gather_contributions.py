"""CPU per entry of gathering an MI ordering's contributions (leftovers 14-misc, issue 27).

``modalinfo.ordering.orderings._contributions`` (numba) plus the sum for Phi_ref, the
term ``GATHER_SECONDS_PER_ENTRY`` of ``modalinfo.ordering.cost`` (1.5 ns per mode and
sample), on 2e5 samples of a 200-frame x 1000-pixel random log, for 150, 500 and 1000
modes (0.22, 0.75, 1.49 GiB); ``time.process_time``, each twice:

    OPENBLAS_NUM_THREADS=1 NUMBA_NUM_THREADS=1 PYTHONPATH=. \\
        python benchmarks/bench_gather_contributions.py
"""

from __future__ import annotations

import time

import numpy as np

from modalinfo.ordering import orderings
from modalinfo.ordering.cost import GATHER_SECONDS_PER_ENTRY


def main(modes=(150, 500, 1000), n=200_000, frames=200, pixels=1000, repeats=2) -> None:
    rng = np.random.default_rng(0)
    for m in modes:
        a = rng.standard_normal((frames, m))
        matrix = rng.standard_normal((pixels, m))
        f = np.sort(rng.integers(0, frames, n)).astype(np.int64)
        p = rng.integers(0, pixels, n).astype(np.int64)
        orderings._contributions(a[:, :2], matrix[:, :2], f[:10], p[:10])  # compile
        for _ in range(repeats):
            t0, w0 = time.process_time(), time.perf_counter()
            c = orderings._contributions(a, matrix, f, p)
            c.sum(axis=0)
            t, w = time.process_time() - t0, time.perf_counter() - w0
            per = t / (m * n)
            print(f"{m} modes x {n} samples ({c.nbytes / 2**30:.2f} GiB): {per * 1e9:.1f} ns "
                  f"per entry, {per / GATHER_SECONDS_PER_ENTRY:.1f} x the model "
                  f"(wall {w:.1f} s)", flush=True)
            del c


if __name__ == "__main__":
    main()
