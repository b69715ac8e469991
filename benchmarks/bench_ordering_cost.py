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
    args = parser.parse_args()

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


if __name__ == "__main__":
    main()
