"""Coverage of ``select``'s gain interval against the block length (left33-ci, issue 27).

Since fix53-b ``_gaussian_block_ci`` is ``conditional_mutual_information_ci``'s interval
(Fisher's z with Bartlett's floor), not the "normal" one this bench measured: run it on
a commit before fix53-b to reproduce left33-ci's table (docs/ADVERSARIAL.md, fix53-b).

Reference: the gain of a Gaussian AR(1) series x_t+1 = phi x_t + e_t,
``I(x_t+1; x_t) = -0.5 ln(1 - phi^2)`` (Cover & Thomas 2006, eq. 8.56; 0 at phi = 0).
Per phi, frame count T and seed s: the series from ``default_rng(1000 + s)`` (500
burn-in frames dropped; the logs of bench_select_coverage_fix33a.py), its lag-1 pair
``(x[1:], x[:-1])``, the gain from ``numpy.corrcoef``, and the 95 % "normal" interval of
``modalinfo.information.selection._gaussian_block_ci`` (what ``select_inputs`` and
``modalinfo select`` print, 199 resamples, ``default_rng(s)``) with the block length
b = the current rule (``auto_block_length``, Politis & White 2004 with Patton, Politis
& White 2009), 2 b, 4 b (capped at n / 2), and with ``--arch`` the reference
implementation ``arch.bootstrap.optimal_block_length`` ("circular" column, the
largest over the pair; bench-only, not a dependency: ``pip install --target DIR
arch`` and put DIR on PYTHONPATH). Printed per cell: the bias and standard deviation
of the gains, the coverage of an interval with their own sd, and per block rule the
median b, the coverage with its Clopper-Pearson 95 % interval (``scipy.stats.beta``),
the misses below / above, and the mean bootstrap SE over the gains' sd.

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=.:DIR nice -n 5 python \\
        benchmarks/bench_select_block_length_left33.py --seeds 300 --phis 0.5,0.9 --arch
"""

from __future__ import annotations

import argparse
import math

import numpy as np
from _common import ar1_lag_pair, clopper_pearson

import modalinfo.information.selection as sel


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--seeds", type=int, default=200)
    p.add_argument("--frames", default="1000,2000")
    p.add_argument("--phis", default="0,0.5,0.9,0.98")
    p.add_argument("--arch", action="store_true")
    a = p.parse_args()
    if a.arch:
        from arch.bootstrap import optimal_block_length as obl
    orig = sel.auto_block_length
    try:
        for phi in (float(v) for v in a.phis.split(",")):
            true = -0.5 * math.log(1 - phi**2) if phi else 0.0
            for T in (int(t) for t in a.frames.split(",")):
                names = ["pw", "2pw", "4pw"] + (["arch"] if a.arch else [])
                res: dict[str, list] = {k: [] for k in names}
                bls: dict[str, list] = {k: [] for k in names}
                g = np.empty(a.seeds)
                for s in range(a.seeds):
                    data, r, gain = ar1_lag_pair(phi, T, 1000 + s)
                    g[s] = gain
                    b0 = orig(data)
                    for k in names:
                        if k == "pw":
                            b = b0
                        elif k == "2pw":
                            b = 2 * b0
                        elif k == "4pw":
                            b = 4 * b0
                        else:
                            b = int(math.ceil(obl(data)["circular"].max()))
                        b = max(1, min(b, data.shape[0] // 2))
                        bls[k].append(b)
                        sel.auto_block_length = lambda d, b=b: b
                        res[k].append(sel._gaussian_block_ci(data, gain, 199, 0.95,
                                                             np.random.default_rng(s)))
                sel.auto_block_length = orig
                sd = g.std(ddof=1)
                tc = np.mean(np.abs(g - true) <= 1.96 * sd)
                print(f"phi={phi} T={T}: true {true:.4f} bias {g.mean() - true:+.4f} "
                      f"sd {sd:.4f} cov(true sd) {tc:.3f}")
                for k in names:
                    lo, hi = np.array(res[k]).T
                    hit = int(np.sum((lo <= true) & (true <= hi)))
                    c = clopper_pearson(hit, a.seeds)
                    se = (hi - lo) / 2 / 1.959964
                    print(f"   {k:5s} b med {np.median(bls[k]):5.0f}: cov {hit}/{a.seeds}="
                          f"{hit / a.seeds:.3f} [{c[0]:.3f},{c[1]:.3f}] below/above "
                          f"{int(np.sum(true < lo))}/{int(np.sum(true > hi))} "
                          f"SE/sd {se.mean() / sd:.3f}", flush=True)
    finally:
        sel.auto_block_length = orig


if __name__ == "__main__":
    main()
