"""A sweep row's error-budget columns state their units and wavelength.

Round 49 PART b, W06: ``closedloop sweep`` wrote ``budget_*_on_axis`` into sweep.csv /
sweep.parquet without a unit (the header and the parquet schema said nothing) while the
run's .h5 gives the same numbers as ``units`` rad^2 at ``wavelength_m`` 6.3e-07 (kaos).
Reference: the kaos preset's science wavelength (``closedloop.presets.kaos().wavelength``,
630 nm) and the .h5 attributes ``ClosedLoopResult.save`` writes (rad^2). The simulation
is replaced by a stand-in result: what is tested is the row, not the simulator.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

import closedloop.training
from closedloop.presets import kaos
from closedloop.sweep import run_one


def test_budget_columns_carry_units_and_wavelength(monkeypatch):
    terms = {t: np.array([0.5, 0.1]) for t in ("fitting", "aliasing", "temporal", "noise",
                                                 "measured")}
    budget = SimpleNamespace(directions=np.array([[5.0, 0.0], [0.0, 0.0]]), **terms)
    fake = SimpleNamespace(summary=lambda: {"strehl_peak_mean": 0.5}, budget=budget)
    monkeypatch.setattr(closedloop.training, "run_trained", lambda *a, **k: fake)
    config = kaos()
    row = run_one({"config": config.to_dict(), "predictor": "none", "duration": 0.01,
                   "seed": 0, "budget_every": 2, "key": "k"})
    assert row["budget_fitting_on_axis"] == 0.1  # the on-axis direction (0, 0)
    assert row["budget_units"] == "rad^2"
    assert row["budget_wavelength_m"] == 6.3e-07 == config.wavelength
