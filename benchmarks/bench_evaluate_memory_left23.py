"""``evaluate``'s tracemalloc peak with an ARMA predictor, and its growth per chunk frame.

Reference: :mod:`tracemalloc`'s peak of each ``evaluate`` call (warm numba, seeded
AR(1) log of 8 modes, H = 10), deterministic for a given code. Two parts:

- the peak at 12,000 and 24,000 frames (chunks of 3,000 frames; and 12,000 frames with
  ``refit_every=500``), the results saved with ``--save`` so that two versions of the
  code can be compared bit for bit (``--compare OTHER.npz``);
- the growth of the peak per chunk frame (chunks of 1,000, 3,000 and 6,000 frames at
  24,000 frames), in ``(chunk, H, M)`` float64 arrays, for ARMA and for the linear
  predictor.

Run on a version of the package by putting it first on ``PYTHONPATH`` (Leftovers
23-misc; benchmarks/RESULTS.md, "left23-misc")::

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. python benchmarks/bench_evaluate_memory_left23.py \\
        --save /tmp/after.npz [--compare /tmp/before.npz]
"""

from __future__ import annotations

import argparse
import time
import tracemalloc

import numpy as np

from modalinfo.forecast import ARMAPredictor, LinearPredictor, evaluate

M, H = 8, 10
KEYS = ("rmse", "coverage", "rmse_wavefront", "dm_statistic", "pvalue", "one_step")


def _log(n_frames: int) -> np.ndarray:
    rng = np.random.default_rng(1)
    x = np.zeros((n_frames, M))
    e = rng.standard_normal((n_frames, M))
    for t in range(1, n_frames):
        x[t] = 0.9 * x[t - 1] + e[t]
    return x


def _peak(preds, x, chunk, refit=None):
    tracemalloc.start()
    try:
        t0 = time.perf_counter()
        ev = evaluate(preds, x, train=0.5, horizons=range(1, H + 1), chunk_frames=chunk,
                      refit_every=refit)
        return ev, tracemalloc.get_traced_memory()[1], time.perf_counter() - t0
    finally:
        tracemalloc.stop()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--save", help="write the results (.npz) for a later --compare")
    parser.add_argument("--compare", help="results of another version (.npz): bit for bit")
    args = parser.parse_args()
    evaluate({"arma": ARMAPredictor(order=(2, 3))},
             np.random.default_rng(0).standard_normal((400, 2)), horizons=range(1, 3))
    res = {}
    print("| frames | refit_every | peak [MB] | peak / (3000, H, M) array | time [s] |")
    print("|---|---|---|---|---|")
    for n_frames, refit in ((12000, None), (24000, None), (12000, 500)):
        ev, peak, dt = _peak({"arma": ARMAPredictor(order=(2, 3))}, _log(n_frames), 3000,
                             refit)
        print(f"| {n_frames} | {refit} | {peak / 1e6:.3f} | {peak / (8 * H * M * 3000):.3f} "
              f"| {dt:.1f} |")
        res.update({f"{n_frames}_{refit}_{k}": getattr(ev, k) for k in KEYS})
    x = _log(24000)
    for preds in ({"arma": ARMAPredictor(order=(2, 3))}, {"linear": LinearPredictor()}):
        peaks = {c: _peak(preds, x, c)[1] for c in (1000, 3000, 6000)}
        per = [(peaks[b] - peaks[a]) / (8 * H * M * (b - a)) for a, b in ((1000, 3000),
                                                                         (3000, 6000))]
        print(f"{next(iter(preds))}: growth per chunk frame {per[0]:.3f} / {per[1]:.3f} "
              "(chunks 1000 -> 3000 / 3000 -> 6000) arrays")
    if args.save:
        np.savez(args.save, **res)
    if args.compare:
        other = np.load(args.compare)
        differ = [k for k in res if res[k].tobytes() != other[k].tobytes()]
        print(f"{len(res)} arrays compared bit for bit with {args.compare}: "
              f"{len(differ)} differ {differ}")


if __name__ == "__main__":
    main()
