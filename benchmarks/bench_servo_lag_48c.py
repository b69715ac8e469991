"""The simulated servo-lag term against wind, and its spectral reference (fix48-c).

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_servo_lag_48c.py [SEEDS]

Round 47 PART a observed the temporal term of the error budget growing as ~v^2, not
Greenwood's v^(5/3). One ground layer (D = 1 m, d/r0 = 10, L0 = 20 m, 64 pixels), an
ideal WFS, a 65-mode Zernike DM (radial orders 1-10), no noise, 1 kHz, full exposure,
0.5 ms delay, gain 0.5; winds 1-30 m/s along x, SEEDS seeds each (default 4), 4 s of loop
at v <= 4 m/s and 2 s above, ``budget_every=1`` (the budget averages the frames after the
loop's settling). The reference is the test's
(tests/closedloop/test_servo_lag_wind_law_fixes48.py ``servo_lag_variance``: von Karman
PSD, Noll's Zernike filter, the integrator's rejection on the simulator's internal-step
timeline, scipy's Gauss-Legendre). Columns: mean temporal term +- its standard error over
the seeds, the reference, their ratio; then the fitted exponent of v (log-log least
squares, standard error from the residuals). Table: benchmarks/RESULTS.md, rows "fix48-c"
(seed k of this script gives the bits of that table's seed k: checked for seed 0).
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np

WINDS = (1, 2, 3, 5, 8, 12, 16, 20, 30)


def _reference_module():
    path = (Path(__file__).resolve().parent.parent / "tests" / "closedloop"
            / "test_servo_lag_wind_law_fixes48.py")
    spec = importlib.util.spec_from_file_location("servo_lag_reference", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def main(seeds: int = 4) -> None:
    from closedloop import simulate

    ref = _reference_module()
    reference = ref.servo_lag_variance(np.array(WINDS, dtype=float))
    print("| v [m/s] | seeds | temporal [rad^2] | reference | ratio |")
    print("|---|---|---|---|---|")
    means = []
    for v, r in zip(WINDS, reference, strict=True):
        runs = [float(simulate(ref._config(float(v)), 4.0 if v <= 4 else 2.0, seed=s,
                               progress=False, budget_every=1).budget.temporal[0])
                for s in range(seeds)]
        m = float(np.mean(runs))
        se = float(np.std(runs, ddof=1) / np.sqrt(seeds)) if seeds > 1 else float("nan")
        means.append(m)
        print(f"| {v} | {seeds} | {m:.4g} +- {se:.2g} | {r:.4g} | {m / r:.3f} +- {se / r:.3f} |",
              flush=True)
    for name, keep in (("1-30", slice(None)), ("1-12", slice(0, 6)), ("12-30", slice(5, None))):
        x = np.log(np.array(WINDS, dtype=float)[keep])
        for what, y in (("simulated", np.log(np.array(means)[keep])),
                        ("reference", np.log(reference[keep]))):
            a = np.vstack([x, np.ones_like(x)]).T
            coef, res, *_ = np.linalg.lstsq(a, y, rcond=None)
            dof = len(x) - 2
            s2 = float(res[0]) / dof if dof > 0 and res.size else 0.0
            se = np.sqrt(s2 * np.linalg.inv(a.T @ a)[0, 0])
            print(f"exponent {name} m/s, {what}: {coef[0]:.3f} +- {se:.3f}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 4)
