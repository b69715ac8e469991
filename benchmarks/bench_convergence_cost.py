"""Benchmark: the cost of ``mutual_information``'s regime rules against a direct estimate.

``mutual_information`` runs the rules of :mod:`modalinfo.information.convergence` after
its estimate (rule 1 O(n), rule 3 one sort of each variable, rule 2 three estimates on
disjoint quarters where the estimate is below the Gaussian MI of its xi or the data
have ties). A direct estimate, ``MutualInformation(method).estimate(x, y)``, runs none.
Printed per method and case: the direct CPU time, ``mutual_information``'s, their
ratio, and whether rule 2 ran (medians of ``--repeats`` calls, ``time.process_time``,
one BLAS thread). Cases: Gaussian pairs at n = 1e4 (``--n``), rho 0, 0.6 and 0.9, and
the zigzag of 10 pieces (where rule 2 runs and warns); the last line per method is the
median ratio over the cases where rule 2 ran.

Run, on the package to measure (PYTHONPATH chooses it: a worktree, or an exported
commit for "before")::

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. python benchmarks/bench_convergence_cost.py
"""

from __future__ import annotations

import argparse
import math
import os
import warnings

import numpy as np
from _common import cpu_median


def _cases(n: int) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    rng = np.random.default_rng(12)
    cases = {}
    for rho in (0.0, 0.6, 0.9):
        x = rng.standard_normal(n)
        cases[f"gauss rho={rho}"] = (x, rho * x + math.sqrt(1 - rho**2) * rng.standard_normal(n))
    x = rng.uniform(0, 1, n)
    u = 10 * x
    k = np.floor(np.minimum(u, 10 - 1e-12))
    cases["zigzag10"] = (x, np.where(k % 2 == 0, u - k, 1 - (u - k))
                         + 0.1 * rng.standard_normal(n))
    return cases


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=10_000)
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--methods", nargs="+", default=["ksg", "kde", "histogram"])
    args = parser.parse_args()

    import modalinfo
    from modalinfo.information import MutualInformation, mutual_information
    from modalinfo.information.convergence import (
        _neighbours,
        effective_sample_rule,
        neighbour_rule,
        xi_gaussian_mi,
    )

    print(f"# package {os.path.dirname(modalinfo.__file__)}, n = {args.n}, "
          f"load {os.getloadavg()[0]:.1f}")
    print(f"{'method':10s}{'case':16s}{'direct ms':>10s}{'rules ms':>10s}{'ratio':>7s}  rule 2")
    for method in args.methods:
        ran = []
        for name, (x, y) in _cases(args.n).items():
            direct = cpu_median(lambda m=method, a=x, b=y: MutualInformation(m).estimate(a, b),
                                args.repeats)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                full = cpu_median(lambda m=method, a=x, b=y: mutual_information(a, b, method=m),
                                  args.repeats)
            value = MutualInformation(method).estimate(x, y)
            xi, ties = _neighbours(x, y)
            # rule 2 runs where rule 1 and rule 3 are silent and (ties or value < bound)
            rule2 = (effective_sample_rule(x, y) is None
                     and (ties or neighbour_rule(x, y, value) is None)
                     and (ties or value < xi_gaussian_mi(xi)))
            if rule2:
                ran.append(full / direct)
            print(f"{method:10s}{name:16s}{direct * 1e3:10.2f}{full * 1e3:10.2f}"
                  f"{full / direct:7.2f}  {'yes' if rule2 else 'no'}")
        if ran:
            print(f"{method:10s}{'median, rule 2':16s}{'':20s}{np.median(ran):7.2f}")
    print(f"# load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
