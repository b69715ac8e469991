"""Benchmark: CPU of MI orderings of 50, 150 and 500 modes against the cost model.

``order_modes`` (default histogram estimator and 40 bootstrap replicates) of a
Kolmogorov-like log (coefficients N(0, (n + 1)^(-11/3)) by radial order n, seed 0) of
``--frames`` frames on a ``--pupil``-pixel pupil (8 x 64 px: 25,728 samples; 20 x 40 px,
25,280 samples, is the shape adversarial round 13 profiled at 150 modes, too coarse for
500 Zernikes), timed by ``time.process_time`` with one
BLAS and numba thread; median of ``--repeats`` runs. Printed: the model of
:func:`modalinfo.ordering.cost.least_ordering_seconds` (the time the library and the
command line check before work), the median measured, their ratio, and the ``score``
calls counted in the run against the model's count.

Run, on the package to measure (PYTHONPATH chooses it)::

    OPENBLAS_NUM_THREADS=1 NUMBA_NUM_THREADS=1 PYTHONPATH=. \\
        python benchmarks/bench_ordering_cost.py --modes 50 150 500 --repeats 3

``--grid`` (fix47-b, issue 27): the estimate against the CPU over estimators x samples per
estimate x modes x replicates x methods (``--estimators``, ``--samples``, ``--modes``,
``--resamples``, ``--methods``) on a 96-pixel pupil (Z2..Z1001 fit), the coefficients
random (the same log law), ``sample_budget`` = the samples; the cells whose estimate
times 4 (the largest ratio seen before) exceeds ``--cap`` CPU seconds are left out and
named. One row per cell: the estimate, the median CPU of ``--repeats`` runs, their
ratio, the MI estimates counted against the model's::

    OPENBLAS_NUM_THREADS=1 NUMBA_NUM_THREADS=1 PYTHONPATH=. nice -n 10 \\
        python benchmarks/bench_ordering_cost.py --grid --repeats 3 --cap 25
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np


def _log(n_modes: int, n_frames: int) -> np.ndarray:
    rng = np.random.default_rng(0)
    j = np.arange(2, 2 + n_modes)
    radial = np.ceil((-3 + np.sqrt(9 + 8 * (j - 1))) / 2)
    return rng.standard_normal((n_frames, n_modes)) * (radial + 1) ** (-11 / 6)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", type=int, nargs="+", default=[50, 150, 500])
    parser.add_argument("--frames", type=int, default=8)
    parser.add_argument("--pupil", type=int, default=64)
    parser.add_argument("--method", default="mi_marginal")
    parser.add_argument("--estimator", default="histogram")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--grid", action="store_true")
    parser.add_argument("--estimators", nargs="+",
                        default=["histogram", "gaussian", "kde", "ksg"])
    parser.add_argument("--samples", type=int, nargs="+",
                        default=[1000, 10_000, 100_000, 200_000])
    parser.add_argument("--resamples", type=int, nargs="+", default=[0, 20])
    parser.add_argument("--methods", nargs="+", default=["mi_marginal", "mi_greedy"])
    parser.add_argument("--cap", type=float, default=25.0)
    args = parser.parse_args()
    if args.grid:
        grid(args)
        return

    from modalinfo.bases import Pupil, ZernikeBasis
    from modalinfo.information import MutualInformation
    from modalinfo.ordering import order_modes
    from modalinfo.ordering.cost import least_ordering_seconds

    pupil = Pupil(args.pupil)
    n = args.frames * pupil.n_valid
    print(f"# {args.method} {args.estimator}, {args.frames} frames x {pupil.n_valid} pixels "
          f"= {n} samples, 40 replicates, load {os.getloadavg()[0]:.1f}")
    print(f"{'modes':>6s}{'model s':>10s}{'measured s':>12s}{'ratio':>7s}"
          f"{'calls model':>13s}{'counted':>9s}   runs")
    original = MutualInformation.score
    for m in args.modes:
        coeffs = _log(m, args.frames)
        basis = ZernikeBasis(pupil, modes=range(2, 2 + m))
        model, calls = least_ordering_seconds(args.estimator, n, m, 40, 1, args.method)
        counted = [0]

        def counting(self, y, _c=counted):
            _c[0] += 1
            return original(self, y)

        MutualInformation.score = counting
        try:
            order_modes(coeffs[:, :min(m, 20)], ZernikeBasis(pupil, modes=range(2, 2 + min(m, 20))),
                        args.method, estimator=args.estimator, n_resamples=1, seed=0)  # JIT
            runs = []
            for _ in range(args.repeats):
                counted[0] = 0
                start = time.process_time()
                order_modes(coeffs, basis, args.method, estimator=args.estimator, seed=0,
                            max_seconds=None)
                runs.append(time.process_time() - start)
        finally:
            MutualInformation.score = original
        med = float(np.median(runs))
        print(f"{m:6d}{model:10.2f}{med:12.2f}{med / model:7.2f}{calls:13d}{counted[0]:9d}   "
              + " ".join(f"{r:.2f}" for r in runs), flush=True)
    print(f"# load {os.getloadavg()[0]:.1f}")


def grid(args: argparse.Namespace) -> None:
    """The ``--grid`` table (module notes)."""
    import warnings

    from modalinfo.bases import Pupil, ZernikeBasis
    from modalinfo.information import MutualInformation
    from modalinfo.ordering import order_modes
    from modalinfo.ordering.cost import least_ordering_seconds

    modes = [m for m in args.modes if m >= 2]
    pupil = Pupil(96)
    cells = []
    for est in args.estimators:
        for n in args.samples:
            for m in modes:
                for r in args.resamples:
                    for method in args.methods:
                        model, calls = least_ordering_seconds(est, n, m, r, 1, method)
                        cells.append((model, est, n, m, r, method, calls))
    cells.sort()
    skipped = [c for c in cells if 4 * c[0] > args.cap]
    cells = [c for c in cells if 4 * c[0] <= args.cap]
    print(f"# grid: {len(cells)} cells, 96-px pupil ({pupil.n_valid} px), cpu, median of "
          f"{args.repeats}, load {os.getloadavg()[0]:.1f}")
    print(f"{'estimator':>10s}{'n':>8s}{'modes':>6s}{'res':>4s}{'method':>12s}"
          f"{'model s':>10s}{'cpu s':>9s}{'ratio':>7s}{'calls':>8s}{'counted':>8s}   runs")
    bases: dict = {}
    original = MutualInformation.score
    counted = [0]

    def counting(self, y):
        counted[0] += 1
        return original(self, y)

    warm: set = set()
    MutualInformation.score = counting
    try:
        for model, est, n, m, r, method, calls in cells:
            if m not in bases:
                bases[m] = ZernikeBasis(pupil, modes=range(2, 2 + m))
            frames = max(4, -(-n // pupil.n_valid) + 1)
            coeffs = _log(m, frames)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                if (est, method) not in warm:  # numba and first-call caches, not timed
                    order_modes(coeffs[:, :3], ZernikeBasis(pupil, modes=range(2, 5)), method,
                                estimator=est, sample_budget=n, n_resamples=1, seed=0,
                                max_seconds=None)
                    warm.add((est, method))
                runs = []
                for _ in range(args.repeats):
                    counted[0] = 0
                    start = time.process_time()
                    order_modes(coeffs, bases[m], method, estimator=est, sample_budget=n,
                                n_resamples=r, seed=0, max_seconds=None)
                    runs.append(time.process_time() - start)
            med = float(np.median(runs))
            print(f"{est:>10s}{n:8d}{m:6d}{r:4d}{method:>12s}{model:10.3f}{med:9.3f}"
                  f"{med / model:7.2f}{calls:8d}{counted[0]:8d}   "
                  + " ".join(f"{t:.3f}" for t in runs), flush=True)
    finally:
        MutualInformation.score = original
    for model, est, n, m, r, method, _ in skipped:
        print(f"# not run (4 x model {4 * model:.0f} s > cap): {est} n={n} modes={m} "
              f"resamples={r} {method}")
    print(f"# load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
