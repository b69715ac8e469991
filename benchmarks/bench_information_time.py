"""Timing of conditional MI and of the greedy input selection, side by side.

Run: /work/main/.venv/bin/python benchmarks/bench_information_time.py [--quick] [--cmi-only]

1. Conditional MI I(X; Y | Z) of a trivariate normal sample at n = 1e3, 1e4, 1e5
   (1e5 skipped with --quick), and at 1e5 with a 3-column z: our histogram estimator
   from the float samples (binning included: default (6 n)^(1/(d+2)) quantile bins
   per axis, Miller-Madow), against infomeasure's ``discrete`` and ``miller_madow``
   estimators given the *same bin codes* (its time excludes the binning; infomeasure
   does not bin floats itself: its discrete estimators take symbols), and against
   the same codes made by numpy (sort, interp, searchsorted: what a user of
   infomeasure would write) plus infomeasure ``miller_madow`` (floats in, value out,
   as ours). KSG (Frenzel-Pompe, k = 3): ours (scipy cKDTree) at every n,
   infomeasure's at 1e3 and 1e4 (at 1e5 it takes minutes). Medians of repeats, the
   first (numba-compiling) call excluded.
2. The greedy selection on the shipped 27-mode closed-loop log
   (data/kaos_like_closed_loop.npz, 8000 frames), lags 0..9 (270 candidates), horizon
   2: one target (Z5) with the defaults (199 surrogates per step, block-bootstrap
   intervals); all 27 targets with intervals off; and the ``info`` predictor's fit
   (27 modes x 10 horizons, extended-BIC stop) on the first half of the log.

3. With ``--coverage`` (instead of 1 and 2): coverage of the nominal 95% block-
   bootstrap interval (:func:`conditional_mutual_information_ci`, 99 resamples, 40
   trials) of the transfer entropy of a bivariate VAR(1) (x_t = 0.6 x_{t-1} +
   0.5 y_{t-1} + e, y_t = 0.8 y_{t-1} + f; TE 0.1854 nats in closed form) at n = 1e3,
   1e4, 1e5 for "gaussian" and "histogram" (and "kde" at 1e3): coverage of the true
   TE and, for the histogram, of its binned estimand I_k (its value at the same bins
   on two 2e6-sample series); mean, sd over trials, mean bootstrap sd and bias; and
   the coverage of the bias-corrected centre ``2 theta - mean(boot)`` and of the basic
   interval. About 10 min on the shared machine (kde: 7 of them).

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
from modalinfo.information import (  # noqa: E402
    conditional_mutual_information,
    conditional_mutual_information_ci,
    select_inputs,
    transfer_entropy_variables,
)
from modalinfo.information.histogram import _bins_per_axis, _group_codes  # noqa: E402
from modalinfo.information.resampling import percentile_bounds  # noqa: E402
from modalinfo.io import load  # noqa: E402

DATA = Path(__file__).resolve().parent.parent / "data" / "kaos_like_closed_loop.npz"
COV = np.array([[2.0, 0.8, 0.9], [0.8, 1.0, 0.4], [0.9, 0.4, 1.5]])


def true_cmi():
    """0.5 ln(det S_xz det S_yz / (det S_z det S_xyz)) of COV (x, y, z = 0, 1, 2)."""
    def ld(i):
        return np.linalg.slogdet(COV[np.ix_(i, i)])[1]
    return 0.5 * (ld([0, 2]) + ld([1, 2]) - ld([2]) - ld([0, 1, 2]))


def median_time(fn, repeats):
    """Median CPU and wall times [s] over ``repeats`` calls, and the last output.

    CPU time of this process (``time.process_time``; every pool is single-threaded), not wall
    time: on the shared machine a millisecond call is descheduled for several times
    its length at a load average of ~10, which wall-time medians measure instead of
    the work. Wall-time medians are printed beside it.
    """
    cpu, wall, out = [], [], None
    for _ in range(repeats):
        c0, t0 = time.process_time(), time.perf_counter()
        out = fn()
        cpu.append(time.process_time() - c0)
        wall.append(time.perf_counter() - t0)
    return float(np.median(cpu)), float(np.median(wall)), out


def numpy_codes(X, k):
    """Quantile bin codes of each column by numpy: sort, interp, searchsorted (as ours)."""
    n = X.shape[0]
    pos = np.linspace(0.0, n - 1.0, k + 1)
    return [np.searchsorted(np.interp(pos, np.arange(n, dtype=float), np.sort(c))[1:-1], c,
                            side="right") for c in X.T]


def mixed_radix(codes, k):
    """One symbol per row of several code columns (infomeasure takes 1-D conditions)."""
    out = np.zeros_like(codes[0])
    for c in codes:
        out = out * k + c
    return out


def bench_cmi(n, repeats, dz=1, ksg=True, im_ksg=True):
    cov = np.eye(2 + dz)
    cov[:3, :3] = COV
    X = np.random.default_rng(0).multivariate_normal(np.zeros(2 + dz), cov, size=n)
    x, y, z = X[:, 0], X[:, 1], X[:, 2:]
    truth = f", true {true_cmi():.4f} nats" if dz == 1 else ""
    print(f"CMI, {2 + dz}-variate normal, z with {dz} column(s), n = {n}{truth}")
    conditional_mutual_information(x[:1000], y[:1000], z[:1000], method="histogram")  # compile
    t_ours, w_ours, v_ours = median_time(
        lambda: conditional_mutual_information(x, y, z, method="histogram"), repeats)
    rows = [("ours histogram (MM, from floats)", t_ours, w_ours, v_ours)]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import infomeasure as im
    except ImportError:  # test extra not installed
        im = None
    k = _bins_per_axis("auto", n, 2 + dz)
    codes = [_group_codes(X[:, j : j + 1], k, "quantile")[0] for j in range(2 + dz)]
    cz = mixed_radix(codes[2:], k)
    if im is not None:
        for approach in ("discrete", "miller_madow"):
            im.cmi(codes[0][:1000], codes[1][:1000], cond=cz[:1000], approach=approach)
            t, w, v = median_time(lambda a=approach: im.cmi(codes[0], codes[1], cond=cz,
                                                         approach=a), repeats)
            rows.append((f"infomeasure {approach} (same codes)", t, w, v))

        def numpy_then_im():
            c = numpy_codes(X, k)
            return im.cmi(c[0], c[1], cond=mixed_radix(c[2:], k), approach="miller_madow")

        t, w, v = median_time(numpy_then_im, repeats)
        rows.append(("numpy binning + infomeasure MM (floats)", t, w, v))
    if ksg:
        t, w, v = median_time(lambda: conditional_mutual_information(x, y, z, method="ksg"), 1)
        rows.append(("ours KSG k=3 (cKDTree)", t, w, v))
        if im is not None and im_ksg:
            t, w, v = median_time(lambda: im.cmi(x, y, cond=z[:, 0], approach="ksg", k=3), 1)
            rows.append(("infomeasure KSG k=3", t, w, v))
    print(f"  ({k} bins per axis)")
    for name, t, wall, v in rows:
        print(f"  {name:<40} {t * 1e3:10.2f} ms CPU ({wall * 1e3:9.2f} ms wall)  {v:.4f} "
              f"nats  CPU time / ours {t / t_ours:8.1f}x")


def var1(n, a, b, c, seed, burn=500):
    """Bivariate VAR(1) as (source y, target x): x_t = a x_{t-1} + c y_{t-1} + e,
    y_t = b y_{t-1} + f (unit noises)."""
    from scipy.signal import lfilter

    e = np.random.default_rng(seed).standard_normal((n + burn, 2))
    y = lfilter([1.0], [1.0, -b], e[:, 1])
    drive = e[:, 0].copy()
    drive[1:] += c * y[:-1]
    return y[burn:], lfilter([1.0], [1.0, -a], drive)[burn:]


def var1_te(a, b, c):
    """TE y -> x (lag 1, history 1) of :func:`var1` (derivation in tests/information)."""
    syy = 1.0 / (1.0 - b * b)
    sxy = c * b * syy / (1.0 - a * b)
    sxx = (1.0 + c * c * syy + 2.0 * a * c * sxy) / (1.0 - a * a)
    return 0.5 * math.log(1.0 + c * c * (syy - sxy * sxy / sxx))


def bench_coverage(trials=40, n_resamples=99, only=None):
    a, b, c = 0.6, 0.8, 0.5
    te = var1_te(a, b, c)
    print(f"coverage of nominal 95% block-bootstrap intervals, VAR(1) TE = {te:.4f} nats, "
          f"{trials} trials, {n_resamples} resamples")
    for method, sizes in (("gaussian", (1_000, 10_000, 100_000)),
                          ("histogram", (1_000, 10_000, 100_000)), ("kde", (1_000,))):
        for n in sizes:
            if only and f"{method}:{n}" not in only:
                continue
            target = te
            if method == "histogram":  # the binned estimand at the default bins for n
                k = _bins_per_axis("auto", n, 3)
                target = float(np.mean([conditional_mutual_information(
                    *transfer_entropy_variables(*var1(2_000_000, a, b, c, 10_000 + s)),
                    bins=k, method="histogram") for s in range(2)]))
            est, sds, bias, cov, cov_k, cov_bc, cov_basic = [], [], [], 0, 0, 0, 0
            t0 = time.perf_counter()
            for s in range(trials):
                x, y, z = transfer_entropy_variables(*var1(n, a, b, c, 500 + s))
                ci = conditional_mutual_information_ci(x, y, z, method=method,
                                                       n_resamples=n_resamples, seed=s)
                th, sd = ci.estimate, ci.bootstrap_std
                est.append(th)
                sds.append(sd)
                bias.append(ci.bootstrap_mean - th)
                cov += ci.low <= te <= ci.high
                cov_k += ci.low <= target <= ci.high
                centre = 2.0 * th - ci.bootstrap_mean
                cov_bc += abs(centre - te) <= 1.959964 * sd
                q_lo, q_hi = percentile_bounds(ci.bootstrap_distribution, 0.95)
                cov_basic += 2.0 * th - q_hi <= target <= 2.0 * th - q_lo
                if (s + 1) % 50 == 0 and s + 1 < trials:  # partial counts of long cells
                    print(f"    {method} n = {n}: {s + 1} trials, coverage: TE {cov}, "
                          f"estimand {cov_k}, BC centre {cov_bc}, basic {cov_basic}",
                          flush=True)
            est = np.asarray(est)
            print(f"  {method:<9} n = {n:>6}: mean {est.mean():.4f} (sd {est.std(ddof=1):.4f}),"
                  f" estimand {target:.4f}, boot sd {np.mean(sds):.4f}, boot bias "
                  f"{np.mean(bias):+.4f}; coverage: TE {cov / trials:.3f}, estimand "
                  f"{cov_k / trials:.3f}, BC centre (TE) {cov_bc / trials:.3f}, basic "
                  f"(estimand) {cov_basic / trials:.3f}; {time.perf_counter() - t0:.0f} s",
                  flush=True)


def bench_selection(quick):
    log = load(DATA)
    print(f"selection on {DATA.name}: {log.n_frames} frames x {log.n_modes} modes, lags 0..9, "
          "horizon 2")
    select_inputs(log, "Z5", horizon=2, max_lag=10, n_surrogates=19, intervals=False)  # warm
    t, _, res = median_time(lambda: select_inputs(log, "Z5", horizon=2, max_lag=10, seed=0), 3)
    print(f"  one target (Z5), 199 surrogates/step + intervals: {t:.2f} s, "
          f"{len(res.inputs)} inputs")
    if not quick:
        t, _, out = median_time(lambda: [select_inputs(log, m, horizon=2, max_lag=10,
                                                    intervals=False, seed=0)
                                      for m in range(log.n_modes)], 1)
        k = np.mean([len(r.inputs) for r in out])
        print(f"  all 27 targets, 199 surrogates/step, no intervals: {t:.2f} s "
              f"({t / log.n_modes:.2f} s per target, mean {k:.1f} inputs)")
    X = np.asarray(log.coeffs)[: log.n_frames // 2]
    t, _, pred = median_time(lambda: InfoPredictor(horizon=10).fit(X), 3)
    print(f"  InfoPredictor fit (27 modes x 10 horizons, EBIC): {t:.2f} s, "
          f"mean {pred.n_inputs_.mean():.1f} inputs per model")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="n <= 1e4, fewer runs")
    parser.add_argument("--cmi-only", action="store_true", help="skip the selection timings")
    parser.add_argument("--coverage", action="store_true", help="interval coverage study only")
    parser.add_argument("--trials", type=int, default=40,
                        help="independent series per cell of --coverage (default 40)")
    parser.add_argument("--cells", default="",
                        help="comma-separated method:n cells of --coverage (default: all), "
                             "e.g. histogram:1000,kde:1000")
    args = parser.parse_args()
    if args.coverage:
        bench_coverage(trials=args.trials,
                       only={c.strip() for c in args.cells.split(",") if c.strip()})
        return
    n = 10_000 if args.quick else 100_000
    bench_cmi(1_000, 9)
    bench_cmi(10_000, 7)
    if not args.quick:
        bench_cmi(100_000, 7, im_ksg=False)
        bench_cmi(100_000, 7, dz=3, ksg=False)
    if not args.cmi_only:
        bench_selection(args.quick)
    print(f"(python {'.'.join(map(str, __import__('sys').version_info[:3]))}, "
          f"load average {os.getloadavg()[0]:.1f}, log2(n) = {math.log2(n):.1f})")


if __name__ == "__main__":
    main()
