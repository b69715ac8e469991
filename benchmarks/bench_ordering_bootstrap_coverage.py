"""Coverage of ``order_modes``' bootstrap bounds on a log whose answer is analytic (issue 27).

Modes: M zero-mean columns over ``n_valid`` pupil pixels, orthogonal with
``sum_p Z_j Z_k = n_valid delta_jk`` (QR of a seeded Gaussian matrix, the constant removed),
coefficients iid N(0, v_k) per frame. With the Gaussian MI estimator without the copula
(Pearson correlation; tests/ordering/test_default_bootstrap_issue27.py) the pooled estimate
of I(Phi_ref; Phi_S) is ``-ln(1 - r^2) / 2`` with ``r^2 = sum_S s_k^2 / sum_all s_k^2`` (the
pixel cross terms vanish exactly), whose truth is the same with the variances v_k:
``I_s = ln(V / R_s) / 2`` with R_s the variance left after step s; the gain of step s is
``ln(R_{s-1} / R_s) / 2`` and the margin ``I_s - ln(V / (R_{s-1} - v_next)) / 2``, along
the order the data chose. Per bound, the share of (repeat, step) pairs whose truth lies
beyond it (nominal (1 - L) / 2 each).

    PYTHONPATH=. OPENBLAS_NUM_THREADS=1 python benchmarks/bench_ordering_bootstrap_coverage.py \
        [--repeats 200] [--resamples 20 40 400]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from modalinfo.ordering import order_modes

VARIANCES = np.array([1.0, 0.7, 0.5, 0.35, 0.25, 0.18])
N_VALID, N_FRAMES = 12, 200


def basis_matrix() -> np.ndarray:
    g = np.random.default_rng(12345).standard_normal((N_VALID, VARIANCES.size + 1))
    g[:, 0] = 1.0  # the constant first, so the other columns are zero-mean
    q, _ = np.linalg.qr(g)
    return q[:, 1:] * np.sqrt(N_VALID)


def truths(order: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    v = VARIANCES[order]
    total = v.sum()
    left = total - np.cumsum(v)  # R_s
    prev = np.concatenate([[total], left[:-1]])
    m = VARIANCES.size
    mi, gain, margin = (np.full(m, np.nan) for _ in range(3))
    mi[:-1] = 0.5 * np.log(total / left[:-1])
    gain[:-1] = 0.5 * np.log(prev[:-1] / left[:-1])
    swapped = prev[:-1] - np.concatenate([v[1:]])
    margin[:-1] = mi[:-1] - 0.5 * np.log(total / swapped)
    return mi, gain, margin


def run(repeats: int, resamples: int, level: float = 0.95) -> dict:
    matrix = basis_matrix()
    miss = {k: np.zeros(2) for k in ("mi", "gain", "margin")}
    count = 0
    cpu = time.process_time()
    for seed in range(repeats):
        rng = np.random.default_rng(seed)
        a = rng.standard_normal((N_FRAMES, VARIANCES.size)) * np.sqrt(VARIANCES)
        res = order_modes(a, matrix, "mi_greedy", estimator="gaussian", seed=seed,
                          estimator_options={"copula": False},
                          n_resamples=resamples, confidence_level=level, block_length=1,
                          sample_budget=N_FRAMES * N_VALID)
        truth = dict(zip(("mi", "gain", "margin"), truths(res.order), strict=True))
        steps = slice(0, VARIANCES.size - 1)
        for k, t in truth.items():
            low = getattr(res, f"{k}_low")[steps]
            high = getattr(res, f"{k}_high")[steps]
            miss[k] += [np.sum(t[steps] < low), np.sum(t[steps] > high)]
        count += VARIANCES.size - 1
    out = {k: (v / count).tolist() for k, v in miss.items()}
    out["cpu_s"] = time.process_time() - cpu
    out["pairs"] = count
    return out


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("--repeats", type=int, default=200)
    p.add_argument("--resamples", type=int, nargs="+", default=[20, 40, 400])
    args = p.parse_args()
    for r in args.resamples:
        out = run(args.repeats, r)
        print(f"R={r:5d} ({out['pairs']} step pairs, {out['cpu_s']:.1f} s CPU): "
              + "; ".join(f"{k} below/above {out[k][0]:.3f}/{out[k][1]:.3f} "
                          f"(coverage {1 - sum(out[k]):.3f})" for k in ("mi", "gain", "margin")),
              flush=True)


if __name__ == "__main__":
    main()
