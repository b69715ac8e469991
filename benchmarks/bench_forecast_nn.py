"""Neural-net forecaster training: the default (L-BFGS stopped at 100 iterations) against
the previous default (500 iterations), time and accuracy in the same run.

Run::

    /work/venv/bin/python benchmarks/bench_forecast_nn.py [--modes 6] [--repeats 1]

On the shipped closed-loop KAOS-like log (``data/kaos_like_closed_loop.npz``), the
first ``--modes`` modes, training on frames 0-6999 and evaluating one-step forecasts
on the rest with :func:`modalinfo.forecast.evaluate`: wall time of the evaluation
(training dominates) and the whole-wavefront one-step gain over persistence, for
``NeuralNetPredictor()`` (max_iter = 100) and ``NeuralNetPredictor(max_iter=500)``.
The machine is shared: the ratio is the figure to read.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from modalinfo.forecast import NeuralNetPredictor, evaluate
from modalinfo.io import load

LOG = Path(__file__).resolve().parent.parent / "data" / "kaos_like_closed_loop.npz"


def _run(pred, log):
    t0 = time.perf_counter()
    ev = evaluate({"nn": pred}, log, train=7000, horizons=[1])
    return time.perf_counter() - t0, float(ev.gain_wavefront[ev.index("nn"), 0])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", type=int, default=6)
    parser.add_argument("--repeats", type=int, default=1)
    args = parser.parse_args()
    log = load(LOG)
    log = log.select(modes=list(log.modes[: args.modes]))
    _run(NeuralNetPredictor(max_iter=1), log)  # warm-up: imports, numba compilation
    rows = {}
    for name, pred in (("ours: max_iter=100 (default)", NeuralNetPredictor()),
                       ("previous: max_iter=500", NeuralNetPredictor(max_iter=500))):
        runs = [_run(pred, log) for _ in range(args.repeats)]
        rows[name] = (float(np.median([r[0] for r in runs])), runs[0][1])
    for name, (t, gain) in rows.items():
        print(f"{name:32s} {t:8.2f} s   one-step gain over persistence {gain:.4f}")
    (t_ours, _), (t_prev, _) = rows.values()
    print(f"ratio (previous / ours): {t_prev / t_ours:.1f}x")


if __name__ == "__main__":
    main()
