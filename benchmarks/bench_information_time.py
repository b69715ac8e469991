"""Timing of conditional MI and of the greedy input selection, side by side.

Run: /work/main/.venv/bin/python benchmarks/bench_information_time.py [--quick]

1. Conditional MI I(X; Y | Z) of a trivariate normal sample at n = 1e5 (skipped with
   --quick) and 2e4: our histogram estimator (from the float samples: binning included,
   default (6 n)^(1/5) quantile bins per axis, Miller-Madow), against infomeasure's
   ``discrete`` and ``miller_madow`` estimators given the *same bin codes* (so its
   time excludes the binning, and the values agree to float rounding), and at 2e4
   KSG (Frenzel-Pompe, k = 3): ours (scipy cKDTree) and infomeasure's. Medians of
   repeats, the first (numba-compiling) call excluded.
2. The greedy selection on the shipped 27-mode closed-loop log
   (data/kaos_like_closed_loop.npz, 8000 frames), lags 0..9 (270 candidates), horizon
   2: one target (Z5) with the defaults (199 surrogates per step, block-bootstrap
   intervals); all 27 targets with intervals off; and the ``info`` predictor's fit
   (27 modes x 10 horizons, extended-BIC stop) on the first half of the log.

Everything runs single-threaded (OpenMP/BLAS pools set to 1 before numpy is
imported): on the shared 2-core machine a multi-threaded OpenBLAS matrix product
under load was measured 50x slower than single-threaded (1.0 s against 0.02 s for a
19 x 8000 by 8000 x 270 product).
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from modalinfo.forecast import InfoPredictor  # noqa: E402
from modalinfo.information import conditional_mutual_information, select_inputs  # noqa: E402
from modalinfo.information.conditional import _bins_per_axis, _group_codes  # noqa: E402
from modalinfo.io import load  # noqa: E402

DATA = Path(__file__).resolve().parent.parent / "data" / "kaos_like_closed_loop.npz"
COV = np.array([[2.0, 0.8, 0.9], [0.8, 1.0, 0.4], [0.9, 0.4, 1.5]])


def true_cmi():
    """0.5 ln(det S_xz det S_yz / (det S_z det S_xyz)) of COV (x, y, z = 0, 1, 2)."""
    def ld(i):
        return np.linalg.slogdet(COV[np.ix_(i, i)])[1]
    return 0.5 * (ld([0, 2]) + ld([1, 2]) - ld([2]) - ld([0, 1, 2]))


def median_time(fn, repeats):
    """Median wall time [s] over ``repeats`` calls, and the last output."""
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), out


def bench_cmi(n, repeats, ksg=True):
    X = np.random.default_rng(0).multivariate_normal(np.zeros(3), COV, size=n)
    x, y, z = X[:, 0], X[:, 1], X[:, 2]
    print(f"CMI, trivariate normal, n = {n}, true {true_cmi():.4f} nats")
    conditional_mutual_information(x[:1000], y[:1000], z[:1000])  # compile
    t_ours, v_ours = median_time(lambda: conditional_mutual_information(x, y, z), repeats)
    rows = [("ours histogram (MM, from floats)", t_ours, v_ours)]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import infomeasure as im
    except ImportError:  # test extra not installed
        im = None
    k = _bins_per_axis("auto", n, 3)
    codes = [_group_codes(X[:, j : j + 1], k, "quantile")[0] for j in range(3)]
    if im is not None:
        for approach in ("discrete", "miller_madow"):
            im.cmi(codes[0][:1000], codes[1][:1000], cond=codes[2][:1000], approach=approach)
            t, v = median_time(lambda a=approach: im.cmi(codes[0], codes[1], cond=codes[2],
                                                         approach=a), max(1, repeats // 2))
            rows.append((f"infomeasure {approach} (same codes)", t, v))
    if ksg:
        t, v = median_time(lambda: conditional_mutual_information(x, y, z, method="ksg"), 1)
        rows.append(("ours KSG k=3 (cKDTree)", t, v))
        if im is not None:
            t, v = median_time(lambda: im.cmi(x, y, cond=z, approach="ksg", k=3), 1)
            rows.append(("infomeasure KSG k=3", t, v))
    for name, t, v in rows:
        print(f"  {name:<38} {t * 1e3:10.1f} ms  {v:.4f} nats  ratio to ours "
              f"{t / t_ours:8.1f}x")


def bench_selection(quick):
    log = load(DATA)
    print(f"selection on {DATA.name}: {log.n_frames} frames x {log.n_modes} modes, lags 0..9, "
          "horizon 2")
    select_inputs(log, "Z5", horizon=2, max_lag=10, n_surrogates=19, intervals=False)  # warm
    t, res = median_time(lambda: select_inputs(log, "Z5", horizon=2, max_lag=10, seed=0), 3)
    print(f"  one target (Z5), 199 surrogates/step + intervals: {t:.2f} s, "
          f"{len(res.inputs)} inputs")
    if not quick:
        t, out = median_time(lambda: [select_inputs(log, m, horizon=2, max_lag=10,
                                                    intervals=False, seed=0)
                                      for m in range(log.n_modes)], 1)
        k = np.mean([len(r.inputs) for r in out])
        print(f"  all 27 targets, 199 surrogates/step, no intervals: {t:.2f} s "
              f"({t / log.n_modes:.2f} s per target, mean {k:.1f} inputs)")
    X = np.asarray(log.coeffs)[: log.n_frames // 2]
    t, pred = median_time(lambda: InfoPredictor(horizon=10).fit(X), 3)
    print(f"  InfoPredictor fit (27 modes x 10 horizons, EBIC): {t:.2f} s, "
          f"mean {pred.n_inputs_.mean():.1f} inputs per model")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="n = 2e4, fewer runs")
    args = parser.parse_args()
    n = 20_000 if args.quick else 100_000
    if not args.quick:  # histograms at 1e5; KSG at 2e4 (infomeasure's takes ~30 s there)
        bench_cmi(n, 5, ksg=False)
    bench_cmi(20_000, 3)
    bench_selection(args.quick)
    print(f"(python {'.'.join(map(str, __import__('sys').version_info[:3]))}, "
          f"load average {os.getloadavg()[0]:.1f}, log2(n) = {math.log2(n):.1f})")


if __name__ == "__main__":
    main()
