"""CPU per call of the default MI / CMI estimator (``ksg``) beside the other methods.

Run (from the repository root)::

    PYTHONPATH=$PWD /work/main/.venv/bin/python benchmarks/bench_mi_default_cost.py

Prints one markdown row per call: two pairs correlated 0.6 (I = 0.2231 nats per pair)
as a pair at n = 1e4, 1e5, 1e6, 1e7 and as 2 x 2 groups at 1e4, 1e5, 1e6
(I = 0.4463), and x, y given K = 5, 10, 20 Gaussian columns at n = 1e4 (the
``cmi-dzK`` tasks of bench_mi_accuracy.py, I = 0.2473). Each cell: median CPU seconds
(``time.process_time``; 3 calls at n = 1e4, 1 above), the estimate in brackets, ``W``
where the call switched method with a ``BiasRuleWarning``, or the time a refusal took
(the size rules refuse before any work). Single-threaded (BLAS pools set to 1 before
numpy loads). Results: benchmarks/RESULTS.md, "The KSG defaults".
"""

import os

if __name__ == "__main__":
    for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(_var, "1")

import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

METHODS = ("ksg", "kde", "histogram", "gaussian")


def cell(fn, reps: int) -> str:
    """Median CPU seconds of ``reps`` calls and the estimate, or the refusal's time."""
    times = []
    t0 = time.process_time()
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            for _ in range(reps):
                t0 = time.process_time()
                value = fn()
                times.append(time.process_time() - t0)
    except ValueError:
        return f"refused in {time.process_time() - t0:.2g} s"
    switched = any(type(w.message).__name__ == "BiasRuleWarning" for w in caught)
    return f"{np.median(times):.3g}{' W' if switched else ''} ({value:.3f})"


def main() -> None:
    from modalinfo.information import conditional_mutual_information, mutual_information

    rng = np.random.default_rng(0)
    print("| call | " + " | ".join(METHODS) + " |")
    print("|---|" + "---:|" * len(METHODS))
    for n in (10_000, 100_000, 1_000_000, 10_000_000):
        x = rng.standard_normal(n)
        y = 0.6 * x + 0.8 * rng.standard_normal(n)
        reps = 3 if n == 10_000 else 1
        row = [cell(lambda m=m, x=x, y=y: mutual_information(x, y, method=m), reps)
               for m in METHODS]
        print(f"| pair, n = {n:.0e} | " + " | ".join(row) + " |", flush=True)
    for n in (10_000, 100_000, 1_000_000):
        x = rng.standard_normal((n, 2))
        y = 0.6 * x + 0.8 * rng.standard_normal((n, 2))
        reps = 3 if n == 10_000 else 1
        row = [cell(lambda m=m, x=x, y=y: conditional_mutual_information(x, y, method=m),
                    reps)
               for m in METHODS]
        print(f"| 2 x 2 groups, n = {n:.0e} | " + " | ".join(row) + " |", flush=True)
    n = 10_000
    for dz in (5, 10, 20):
        z = rng.standard_normal((n, dz))
        w = 1 / np.sqrt(dz)
        x = z.sum(1) * w + rng.standard_normal(n)
        y = 0.8 * x + z.sum(1) * w + rng.standard_normal(n)
        row = [cell(lambda m=m, x=x, y=y, z=z: conditional_mutual_information(
                    x, y, z, method=m), 1)
               for m in METHODS]
        print(f"| x, y given {dz}, n = 1e4 | " + " | ".join(row) + " |", flush=True)


if __name__ == "__main__":
    main()
