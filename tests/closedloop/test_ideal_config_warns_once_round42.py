"""The error budget's ideal-sensor config does not repeat the config's warnings (round 42 PART b).

docs/ADVERSARIAL.md, "Round 42 PART b, issue 27" (B29 / B46 / B47, seen after the
table): ``closedloop run --budget-every 2`` of a config with D/r0 = 1e-6 printed the
"total r0 ... beyond 1 m" warning twice, against the project's "one warning per call":
``ideal_sensor_config`` (the budget's second model, and ``estimate``'s count of it)
validated the same layers again.

Reference: counting, outside the code. Loading the config warns once (its r0 is 700 km,
beyond the 1 m rule); the ideal-sensor copy of it, which changes only the WFSs to
noise-free ideal ones, must add no warning, and the estimate with the budget none.
"""

from __future__ import annotations

import warnings

from closedloop import presets
from closedloop.config import SimulationConfig
from closedloop.resources import estimate, ideal_sensor_config


def test_ideal_copy_and_budget_estimate_add_no_warning():
    d = presets.kaos().to_dict()
    for layer in d["layers"]:
        layer["d_over_r0"] = 1e-6
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        config = SimulationConfig.from_dict(d)
        assert len(caught) >= 1  # the config's own warning (r0 far beyond 1 m)
        before = len(caught)
        ideal = ideal_sensor_config(config)
        estimate(config, 0.01, budget=2)
    assert len(caught) == before, [str(w.message)[:80] for w in caught[before:]]
    assert all(w.kind == "ideal" and w.noise == 0.0 for w in ideal.wfss)
