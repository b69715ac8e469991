"""Time and memory of the ``multivariate`` preset's fit (``alpha="gcv"``) (fix49-b).

Run (before / after: the tree first on the path is the one measured):
``OPENBLAS_NUM_THREADS=1 PYTHONPATH=<tree> python benchmarks/bench_gcv_fit_49b.py``

For each size, ``MultivariatePredictor(order=4, alpha="gcv").fit`` on a seeded Gaussian
history ``(T, M)``: CPU time (``time.process_time``, median of 3 fits after one warm-up),
tracemalloc's peak of one fit in copies of the history (``8 T M`` bytes), and the same for
the fixed ``alpha=1e-3`` fit for comparison. Table: benchmarks/RESULTS.md, "fix49-b".
"""

from __future__ import annotations

import time
import tracemalloc

import numpy as np

from modalinfo.forecast import MultivariatePredictor

SIZES = ((8000, 27), (40000, 27), (20000, 50))


def _measure(x, alpha):
    MultivariatePredictor(order=4, alpha=alpha).fit(x)  # warm-up
    times = []
    for _ in range(3):
        t0 = time.process_time()
        pred = MultivariatePredictor(order=4, alpha=alpha).fit(x)
        times.append(time.process_time() - t0)
    tracemalloc.start()
    MultivariatePredictor(order=4, alpha=alpha).fit(x)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return float(np.median(times)), peak / x.nbytes, pred.alpha_


def main() -> None:
    print("| T | M | gcv CPU s | gcv peak copies | gcv alpha_ | alpha 1e-3 CPU s "
          "| alpha 1e-3 peak copies |")
    print("|---|---|---|---|---|---|---|")
    for n, m in SIZES:
        x = np.random.default_rng(0).standard_normal((n, m))
        g_t, g_p, g_a = _measure(x, "gcv")
        f_t, f_p, _ = _measure(x, 1e-3)
        print(f"| {n} | {m} | {g_t:.3f} | {g_p:.1f} | {g_a:.3g} | {f_t:.3f} | {f_p:.1f} |")


if __name__ == "__main__":
    main()
