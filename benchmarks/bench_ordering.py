"""Timing of the MI orderings (greedy and marginal) against naive alternatives.

Run: /work/venv/bin/python benchmarks/bench_ordering.py [--quick]

Setup (the brief's target case): the KAOS-like closed-loop log, 7000 frames x 27
Zernike modes (Z2-Z28), 64-pixel pupil (3228 valid pixels), 2e5 (frame, pixel)
samples, histogram estimator with its default options. Timed, medians after a warm-up:

- ours: ``order_modes(..., "mi_greedy")`` (one ``MutualInformation.fit`` on Phi_ref,
  Phi_S kept on the samples, one ``score`` per remaining mode and step), without and
  with the block-bootstrap gain bounds (20 replicates); ``"mi_marginal"``;
- naive: the same greedy search with one-shot ``mutual_information(ref, y)`` calls
  (nothing cached) and the partial wavefront re-summed from the contributions of S+k
  for every candidate;
- scikit-learn: the greedy search with ``sklearn.feature_selection.mutual_info_regression``
  (KSG, k = 3), which a user might pick; at 2e5 samples one call takes seconds, so it is
  run in full on a small budget (5000 samples) against our greedy with our KSG
  estimator on the same samples, and its one-step time at 2e5 is extrapolated.
"""

import argparse
import functools

import numpy as np
from _common import timed
from sklearn.feature_selection import mutual_info_regression

from modalinfo.bases import KLBasis, Pupil, ZernikeBasis, zernike_covariance
from modalinfo.information import mutual_information
from modalinfo.ordering import fitting_error, order_modes, sample_contributions
from modalinfo.telemetry.synthetic import kaos_like

median_time = functools.partial(timed, warm=False)  # wall time, every call timed


def naive_greedy(contrib, score_fn):
    """Greedy forward selection recomputing everything for every candidate."""
    ref = contrib.sum(axis=0)
    remaining = list(range(contrib.shape[0]))
    chosen = []
    while len(remaining) > 1:
        values = [score_fn(ref, contrib[chosen + [k]].sum(axis=0)) for k in remaining]
        best = remaining[int(np.argmax(values))]
        chosen.append(best)
        remaining.remove(best)
    return chosen + remaining


def sklearn_mi(ref, y):
    return mutual_info_regression(y[:, None], ref, n_neighbors=3, random_state=0)[0]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    args = parser.parse_args()
    repeats = 2 if args.quick else 3

    log = kaos_like(n_frames=7000, closed_loop=True, seed=0)
    zb = ZernikeBasis(Pupil(64))
    budget = 200_000
    print(f"log {log.n_frames} x {log.n_modes}, pupil 64 px ({zb.pupil.n_valid} valid), "
          f"budget {budget}, histogram estimator (default options)")
    order_modes(log[:200], zb, "mi_greedy", sample_budget=5000, seed=0, n_resamples=2)  # warm-up

    rows = []
    t_greedy, res = median_time(
        lambda: order_modes(log, zb, "mi_greedy", sample_budget=budget, seed=0, n_resamples=0),
        repeats)
    rows.append(("ours: mi_greedy (no bounds)", t_greedy))
    t_boot, res_b = median_time(
        lambda: order_modes(log, zb, "mi_greedy", sample_budget=budget, seed=0, n_resamples=20),
        max(1, repeats - 1))
    rows.append(("ours: mi_greedy + 20 bootstrap replicates", t_boot))
    t_marg, _ = median_time(
        lambda: order_modes(log, zb, "mi_marginal", sample_budget=budget, seed=0,
                            n_resamples=0), repeats)
    rows.append(("ours: mi_marginal (no bounds)", t_marg))

    contrib = sample_contributions(log, zb, sample_budget=budget, seed=0)
    t_naive, naive_order = median_time(
        lambda: naive_greedy(contrib, lambda r, y: mutual_information(r, y, method="histogram")),
        1)
    rows.append(("naive: one-shot mutual_information, re-summed", t_naive))
    same = np.array_equal(np.asarray(naive_order), res.order)

    # scikit-learn KSG on a small budget, against our KSG greedy on the same samples
    small = 5000
    t_ours_ksg, res_ksg = median_time(
        lambda: order_modes(log, zb, "mi_greedy", estimator="ksg", sample_budget=small, seed=0,
                            n_resamples=0), repeats)
    small_contrib = sample_contributions(log, zb, sample_budget=small, seed=0)
    t_sk, sk_order = median_time(lambda: naive_greedy(small_contrib, sklearn_mi), 1)
    ref = contrib.sum(axis=0)
    t_one, _ = median_time(lambda: sklearn_mi(ref, contrib[0]), 3)
    n_calls = contrib.shape[0] * (contrib.shape[0] + 1) // 2 - 1
    rows.append((f"ours: mi_greedy, KSG, {small} samples", t_ours_ksg))
    rows.append((f"scikit-learn mutual_info_regression greedy, {small} samples", t_sk))
    rows.append((f"scikit-learn greedy at {budget} (extrapolated: {n_calls} calls x "
                 f"{t_one:.2f} s)", t_one * n_calls))

    width = max(len(r[0]) for r in rows)
    print(f"{'case':<{width}}  {'time [s]':>9}")
    for name, t in rows:
        print(f"{name:<{width}}  {t:>9.2f}")
    print(f"greedy target (< 10 s): {'met' if t_greedy < 10 else 'NOT met'} ({t_greedy:.2f} s)")
    print(f"naive / ours (histogram greedy): {t_naive / t_greedy:.1f}x; "
          f"same order: {same}")
    print(f"scikit-learn / ours (KSG greedy, {small} samples): {t_sk / t_ours_ksg:.1f}x; "
          f"same order: {np.array_equal(np.asarray(sk_order), res_ksg.order)}")
    print(f"scikit-learn extrapolated at {budget} / ours histogram: "
          f"{t_one * n_calls / t_greedy:.0f}x")
    print("greedy order:", " ".join(res.labels))
    print("gains significantly > 0 for the first", res_b.n_informative, "steps")
    kolmogorov_report(zb)


def kolmogorov_report(zb):
    """Open-loop Kolmogorov log: theoretical K-L vs standard Zernike vs MI orders."""
    modes = list(range(2, 29))
    cov = zernike_covariance(modes) * 20.0 ** (5 / 3)  # D/r0 = 20, rad^2
    a = np.random.default_rng(0).multivariate_normal(np.zeros(27), cov, size=3000)
    kl = KLBasis.from_turbulence(zb.pupil, 27, zernike_modes=modes)
    akl = kl.coefficients_from_zernike(a)
    curves = {
        "Zernike standard": fitting_error(a, zb),
        "K-L theory, variance order": fitting_error(akl, kl),
        "Zernike MI greedy": fitting_error(a, zb, order_modes(
            a, zb, "mi_greedy", sample_budget=100_000, seed=0, n_resamples=0)),
        "K-L theory MI greedy": fitting_error(akl, kl, order_modes(
            akl, kl, "mi_greedy", sample_budget=100_000, seed=0, n_resamples=0)),
    }
    ref = curves["Zernike standard"].mean[:-1]
    print("\nopen-loop Kolmogorov log (3000 frames from zernike_covariance, D/r0 = 20):")
    print(f"{'ordering':<28} {'n for 10%':>9} {'n for 2%':>9} {'ratio to Z std (min..max)':>27}")
    for name, res in curves.items():
        ratio = res.mean[:-1] / ref
        print(f"{name:<28} {res.modes_to_reach_fraction(0.1):>9d} "
              f"{res.modes_to_reach_fraction(0.02):>9d} "
              f"{ratio.min():>13.3f}..{ratio.max():.3f}")


if __name__ == "__main__":
    main()
