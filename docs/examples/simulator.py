"""The MCAO simulator in Python (the README's example; run from the repository root).

Run: ``python docs/examples/simulator.py [DURATION]`` (seconds of simulated time;
the README's 0.5 s takes a few minutes on two cores).
"""

import sys

from closedloop import presets, simulate

duration = float(sys.argv[1]) if len(sys.argv) > 1 else 0.5
result = simulate(presets.get("table1"), duration, seed=0, budget_every=5)
print(result.summary()["strehl_peak_mean"], result.corrected_fov_diameter(0.3))  # after closure
print(result.strehl_map().shape)
print(result.budget.table())  # fitting, aliasing, temporal, noise vs measured
print(result.logs["dm0.pol"])  # a ModalLog: modalinfo reorder / forecast read it
