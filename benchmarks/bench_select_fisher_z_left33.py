"""``select``'s gain interval: half-length blocks and a Fisher-z interval (left33-ci).

Since fix53-b ``_gaussian_block_ci`` is ``conditional_mutual_information_ci``'s interval
(Fisher's z with Bartlett's floor), not the "normal" one this bench measured: run it on
a commit before fix53-b to reproduce left33-ci's table (docs/ADVERSARIAL.md, fix53-b).

Reference: the Gaussian AR(1) gain ``-0.5 ln(1 - phi^2)`` (Cover & Thomas 2006, eq.
8.56) on the logs of bench_select_block_length_left33.py (``default_rng(1000 + s)``,
500 burn-in frames). Per cell, coverage of: the 95 % "normal" interval
``_gaussian_block_ci`` prints (Politis-White block b); the same 199 resamples
(re-drawn here, checked equal to within 1e-6) mapped to Fisher's z of the equivalent
correlation, ``z = atanh(sqrt(1 - exp(-2 I)))``, a normal interval there and mapped
back (a variance-stabilising transform, Fisher 1921; the candidate of "Leftovers
19-ci"), with its misses below / above; and the "normal" interval with blocks of b / 2.

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. nice -n 5 python \\
        benchmarks/bench_select_fisher_z_left33.py 300 0.5,0.9,0.98
"""

from __future__ import annotations

import math
import sys

import numpy as np
from _common import ar1_lag_pair

import modalinfo.information.selection as sel
from modalinfo.information.resampling import auto_block_length


def _gain(z: float) -> float:
    return -0.5 * math.log(1 - math.tanh(z) ** 2)


def main() -> None:
    S = int(sys.argv[1])
    phis = [float(v) for v in sys.argv[2].split(",")]
    try:
        for phi in phis:
            true = -0.5 * math.log(1 - phi**2)
            for T in (1000, 2000):
                hz = hh = hn = hz_lo = hz_hi = 0
                for s in range(S):
                    data, r, gain = ar1_lag_pair(phi, T, 1000 + s)
                    b = auto_block_length(data)
                    lo, hi = sel._gaussian_block_ci(data, gain, 199, 0.95,
                                                    np.random.default_rng(s))
                    dd = sel._gaussian_block_gains(data, 199, np.random.default_rng(s),
                                                   block_length=b)
                    hw = 1.959964 * dd.std(ddof=1)
                    assert abs((gain - hw) - lo) < 1e-6, (lo, gain - hw)  # same draws
                    zs = np.arctanh(np.sqrt(1 - np.exp(-2 * dd)))
                    z0 = math.atanh(abs(r))
                    hz_ = 1.959964 * zs.std(ddof=1)
                    zlo, zhi = _gain(max(z0 - hz_, 0.0)), _gain(z0 + hz_)
                    hz += zlo <= true <= zhi
                    hz_lo += true < zlo
                    hz_hi += true > zhi
                    half = max(1, b // 2)
                    sel.auto_block_length = lambda d, h=half: h
                    lo2, hi2 = sel._gaussian_block_ci(data, gain, 199, 0.95,
                                                      np.random.default_rng(s))
                    sel.auto_block_length = auto_block_length
                    hh += lo2 <= true <= hi2
                    hn += lo <= true <= hi
                print(f"phi={phi} T={T}: normal(pw) {hn / S:.3f}  fisher-z(pw) {hz / S:.3f} "
                      f"(below/above {hz_lo}/{hz_hi})  normal(0.5 pw) {hh / S:.3f}", flush=True)
    finally:
        sel.auto_block_length = auto_block_length


if __name__ == "__main__":
    main()
