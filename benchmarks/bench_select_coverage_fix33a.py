"""Coverage of ``select_inputs``' block-bootstrap gain interval on AR(1) logs (fix33-a).

Reference: for a Gaussian AR(1) series x_t+1 = phi x_t + e_t (phi = 0.9) the gain of
its first input, ``I(x_t+1; x_t) = -0.5 ln(1 - phi^2)`` = 0.830 nats (Cover & Thomas
2006, eq. 8.56). Per frame count T and seed s: the series from ``default_rng(1000 + s)``
(500 burn-in frames dropped), one call ``select_inputs(x, 0, max_lag=1,
n_surrogates=19, max_inputs=1, seed=s)`` (default 199 resamples, 95 % "normal"
interval). Printed per T: the coverage of the true gain with its Clopper-Pearson 95 %
interval (``scipy.stats.beta``), on which side the misses fall, the bias of the gains,
the standard deviation of the gains against the mean bootstrap standard error
(half-width / 1.96), the coverage an interval with the gains' own standard deviation
would have, and the median automatic block length.

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. nice python benchmarks/bench_select_coverage_fix33a.py \\
        --seeds 200 --frames 1000,2000
"""

from __future__ import annotations

import argparse
import warnings

import numpy as np
from _common import clopper_pearson
from scipy import stats

from modalinfo.information.resampling import auto_block_length
from modalinfo.information.selection import select_inputs

PHI = 0.9
TRUE = -0.5 * np.log(1 - PHI**2)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=200)
    parser.add_argument("--frames", default="1000,2000")
    args = parser.parse_args()
    for n_frames in (int(t) for t in args.frames.split(",")):
        g, lo, hi, bl = (np.empty(args.seeds) for _ in range(4))
        for s in range(args.seeds):
            e = np.random.default_rng(1000 + s).standard_normal(n_frames + 500)
            x = np.empty_like(e)
            x[0] = e[0]
            for t in range(1, e.size):
                x[t] = PHI * x[t - 1] + e[t]
            x = x[500:, None]
            bl[s] = auto_block_length(np.column_stack([x[1:, 0], x[:-1, 0]]))
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = select_inputs(x, 0, max_lag=1, n_surrogates=19, max_inputs=1, seed=s)
            first = r.inputs[0]
            g[s], lo[s], hi[s] = first.gain, first.low, first.high
        hit = int(np.sum((lo <= TRUE) & (TRUE <= hi)))
        cp = clopper_pearson(hit, args.seeds)
        sd = g.std(ddof=1)
        se = (hi - lo) / 2 / stats.norm.ppf(0.975)
        print(f"T={n_frames}: coverage {hit}/{args.seeds} = {hit / args.seeds:.3f} "
              f"(CP 95 % [{cp[0]:.3f}, {cp[1]:.3f}]); true gain below the interval "
              f"{int(np.sum(TRUE < lo))}, above {int(np.sum(TRUE > hi))}; bias "
              f"{g.mean() - TRUE:+.4f} +- {sd / np.sqrt(args.seeds):.4f} nats; sd of the gains "
              f"{sd:.4f}, mean bootstrap SE {se.mean():.4f} (ratio {se.mean() / sd:.3f}); "
              f"coverage with the gains' sd {np.mean(np.abs(g - TRUE) <= 1.96 * sd):.3f}; "
              f"median block length {np.median(bl):.0f}", flush=True)


if __name__ == "__main__":
    main()
