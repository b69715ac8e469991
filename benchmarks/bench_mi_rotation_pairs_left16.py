"""Size of the circular MI test against its effective-pairs rule (issue 27, left16-pins).

Independent AR(1) pairs (x and y of the same coefficient, seeded ``[seed, phi code, i]``),
``mutual_information_permutation_test(method="gaussian", permutation="circular",
n_permutations=99)`` with its defaults (matched ends); for each draw the p-value and the
rule's statistic, ``n (1 - p) / (1 + p)`` with p the product of the two lag-1
autocorrelations (``bartlett_pairs``) on the matched window (``matched_window``, the
rows the test keeps), and whether the rule warned. Prints the rejection
rate at 5 % by bins of the statistic, with the draws per bin and the binomial 95 % upper
edge of a 5 % test. Table: benchmarks/RESULTS.md, "left16-pins".

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_mi_rotation_pairs_left16.py DRAWS N PHI...
"""

from __future__ import annotations

import sys
import warnings

import numpy as np
from scipy import stats
from scipy.signal import lfilter

from modalinfo._stats import lag1_autocorrelation
from modalinfo.information import mutual_information_permutation_test
from modalinfo.information.convergence import bartlett_pairs
from modalinfo.information.resampling import matched_window

EDGES = (0.0, 4.0, 6.0, 8.0, 10.0, 14.0, 20.0, np.inf)


def main(draws: int, n: int, phis: list[float]) -> None:
    rows = []
    for phi in phis:
        for i in range(draws):
            rng = np.random.default_rng([20261129, int(round(phi * 1e4)), n, i])
            e = rng.standard_normal((n + 1000, 2))
            x = lfilter([1.0], [1.0, -phi], e[:, 0])[1000:]
            y = lfilter([1.0], [1.0, -phi], e[:, 1])[1000:]
            # the rule judges the matched window the test uses (its default ends)
            a0, b0 = matched_window(x, y)
            stat = bartlett_pairs(b0 - a0, lag1_autocorrelation(x[a0:b0])
                                  * lag1_autocorrelation(y[a0:b0]))
            with warnings.catch_warnings(record=True) as got:
                warnings.simplefilter("always")
                res = mutual_information_permutation_test(
                    x, y, method="gaussian", n_permutations=99, permutation="circular",
                    seed=i)
            warned = any("effective pairs" in str(w.message) for w in got)
            rows.append((phi, stat, res.pvalue, warned))
    a = np.array(rows)
    print(f"n = {n}, draws per phi {draws}, phis {phis}")
    print(f"rule's decision (statistic < 8) against the warning: "
          f"{int(np.sum((a[:, 1] < 8) != (a[:, 3] > 0)))} of {len(a)} differ")
    print("| n_eff bin | draws | size 5 % | binomial 95 % upper edge | warned |")
    for lo, hi in zip(EDGES[:-1], EDGES[1:], strict=True):
        sel = (a[:, 1] >= lo) & (a[:, 1] < hi)
        k = int(sel.sum())
        if k == 0:
            continue
        rej = float(np.mean(a[sel, 2] <= 0.05))
        upper = stats.binom.ppf(0.975, k, 0.05) / k
        print(f"| [{lo:g}, {hi:g}) | {k} | {rej:.3f} | {upper:.3f} | {int(a[sel, 3].sum())} |")
    for phi in phis:
        sel = a[:, 0] == phi
        print(f"phi {phi}: size {np.mean(a[sel, 2] <= 0.05):.3f}, warned "
              f"{int(a[sel, 3].sum())} of {int(sel.sum())}, median n_eff "
              f"{np.median(a[sel, 1]):.1f}")


if __name__ == "__main__":
    main(int(sys.argv[1]), int(sys.argv[2]), [float(p) for p in sys.argv[3:]])
