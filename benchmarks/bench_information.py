"""Timing and accuracy of modalinfo's MI estimators against the usual alternatives.

Run: /work/venv/bin/python benchmarks/bench_information.py [--quick]

For n = 1e4, 1e5, 1e6 samples of a bivariate normal pair (rho = 0.6, true MI
-0.5 ln(1 - rho^2) = 0.2231 nats), times our histogram and KDE MI (one-shot, and
``MutualInformation.fit(x)`` once + ``.score(y)``), scikit-learn's
``mutual_info_regression`` (KSG, k = 3) and a ``numpy.histogram2d`` plug-in MI with
the same bins. Medians over repeats; the first (numba-compiling) call is excluded.
scikit-learn is skipped at a size where its extrapolated time exceeds 60 s.
Everything runs single-threaded (OpenMP/BLAS thread pools set to 1 before numpy is
imported): on a shared 2-core machine, idle OpenMP worker threads left spinning after
scikit-learn's neighbour search otherwise inflate every later timing 2-3 times.
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402
from functools import partial  # noqa: E402

import numpy as np  # noqa: E402
from sklearn.feature_selection import mutual_info_regression  # noqa: E402

from modalinfo.information import MutualInformation, mutual_information  # noqa: E402
from modalinfo.information.histogram import _hacine_gharbi_joint  # noqa: E402

RHO = 0.6
TRUTH = -0.5 * math.log(1 - RHO**2)


CPU = {}


def median_time(fn, repeats):
    """Median wall time [s] and output; the median CPU time is kept in CPU[fn-name]."""
    times, cpu = [], []
    out = None
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fn()
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    CPU["last"] = float(np.median(cpu))
    return float(np.median(times)), out


def histogram2d_mi(x, y, k):
    c, _, _ = np.histogram2d(x, y, bins=k)
    n = c.sum()
    px, py = c.sum(1), c.sum(0)
    nz = c > 0
    mi = np.sum(c[nz] * np.log(c[nz] * n / np.outer(px, py)[nz])) / n
    return mi - (nz.sum() - (px > 0).sum() - (py > 0).sum() + 1) / (2 * n)


def sklearn_ksg(x, y):
    return mutual_info_regression(x[:, None], y, n_neighbors=3, random_state=0)[0]


def run_size(n, rng, reps, sk_budget):
    """Time every estimator on one sample size; return the table row and cache rows."""
    x = rng.standard_normal(n)
    y = RHO * x + math.sqrt(1 - RHO**2) * rng.standard_normal(n)
    t_h, v_h = median_time(partial(mutual_information, x, y, method="histogram"), reps)
    c_h = CPU["last"]
    k = _hacine_gharbi_joint(n, float(np.corrcoef(x, y)[0, 1]))
    t_2d, v_2d = median_time(partial(histogram2d_mi, x, y, k), reps)
    assert abs(v_2d - v_h) < 1e-9  # same estimate, different implementation
    t_k, v_k = median_time(partial(mutual_information, x, y, method="kde"), reps)
    c_k = CPU["last"]
    if sk_budget > 60:
        t_s = v_s = c_s = math.nan
    else:
        t_s, v_s = median_time(partial(sklearn_ksg, x, y), 1 if n > 10_000 else 3)
        c_s = CPU["last"]
    row = (f"| {n:.0e} | {1e3 * t_h:.1f} ({1e3 * c_h:.1f}) | {1e3 * t_2d:.1f} | "
           f"{1e3 * t_k:.1f} ({1e3 * c_k:.1f}) | "
           + (f"{1e3 * t_s:.0f} ({1e3 * c_s:.0f})" if t_s == t_s
              else f"skipped (~{sk_budget:.0f} s)")
           + f" | {v_h - TRUTH:+.4f} | {v_k - TRUTH:+.4f} | "
           + (f"{v_s - TRUTH:+.4f}" if v_s == v_s else "-")
           + f" | {t_s / t_h:.0f} ({c_s / c_h:.0f}) | {t_s / t_k:.0f} ({c_s / c_k:.0f}) | "
           f"{t_2d / t_h:.1f} |")
    cache = []
    for method, t_one in (("histogram", t_h), ("kde", t_k)):
        est = MutualInformation(method)
        t_fit, _ = median_time(partial(est.fit, x), reps)
        t_score, _ = median_time(partial(est.score, y), reps)
        cache.append(f"| {n:.0e} | {method} | {1e3 * t_fit:.1f} | {1e3 * t_score:.1f} | "
                     f"{1e3 * t_one:.1f} | {t_one / t_score:.1f} |")
    return row, cache, t_s


def greedy_like(rng, n=200_000, n_scores=400):
    """Total time of fit(x) once + n_scores score(y) calls, as the greedy MI ordering."""
    x = rng.standard_normal(n)
    ys = [a * x + rng.standard_normal(n) for a in np.linspace(0.1, 3.0, 20)]
    lines = []
    for method in ("histogram", "kde"):
        t0, c0 = time.perf_counter(), time.process_time()
        est = MutualInformation(method).fit(x)
        for i in range(n_scores):
            est.score(ys[i % len(ys)])
        lines.append(f"| {method} | {n:.0e} | {n_scores} | {time.perf_counter() - t0:.2f} | "
                     f"{time.process_time() - c0:.2f} |")
    return lines


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    args = parser.parse_args()
    reps = 3 if args.quick else 7
    rng = np.random.default_rng(0)
    # compile the numba kernels outside the timings
    mutual_information(rng.standard_normal(100), rng.standard_normal(100), method="kde")
    mutual_information(rng.standard_normal(100), rng.standard_normal(100), method="histogram")
    print(f"true MI = {TRUTH:.4f} nats (rho = {RHO}); times are wall-clock medians in ms, "
          "(CPU-time medians in brackets: the machine is shared)\n")
    print("| n | ours hist | np.histogram2d | ours KDE | sklearn KSG | hist err | KDE err "
          "| KSG err | KSG/hist | KSG/KDE | h2d/hist |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    cache_rows = []
    sk_budget = 0.0
    for n in (10_000, 100_000, 1_000_000):
        row, cache, t_s = run_size(n, rng, reps, sk_budget)
        print(row, flush=True)
        cache_rows += cache
        # KSG is O(n log n): extrapolate to the next size (x 10) to decide whether to run
        sk_budget = t_s * 10 * math.log(10 * n) / math.log(n) if t_s == t_s else math.inf
    print("\n| n | method | fit(x) ms | score(y) ms | one-shot ms | one-shot/score |")
    print("|---|---|---|---|---|---|")
    print("\n".join(cache_rows))
    print("\nGreedy-search pattern: fit(x) once, then score(y) 400 times\n")
    print("| method | n | scores | wall s | CPU s |")
    print("|---|---|---|---|---|")
    print("\n".join(greedy_like(rng)))


if __name__ == "__main__":
    main()
