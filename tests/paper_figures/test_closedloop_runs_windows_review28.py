"""The progress line of ``run_all``: two windows when the runs close apart (review28, round 28).

``closedloop_runs.run_all`` logs each run's SR peak averaged "from the no-prediction run's
closure" (the report's window, Figure 2) and its FoV "from its own closure". The round 43
test gave every run the same window, so planted bugs R28-P2 (the SR averaged from the
run's own window) and R28-P5 (its own closure time printed as the no-prediction one)
escaped ``test_mutation_gaps_closedloop_runs.py``. Reference: the means of the SR values
written here, by hand, and the times written here. No loop runs.
"""

from __future__ import annotations

import closedloop.simulation
import closedloop.training
from paper_figures import closedloop_runs as cr


class _Result:
    def __init__(self, start):
        self.times = [0.001, 0.002, 0.003, 0.004]
        self.strehl_peak = [0.25, 0.5, 0.75, 1.0]
        self.averaging_start = start
        self.closure_index = start

    def summary(self):
        return {"strehl_peak_mean": -1.0, "corrected_fov_diameter_arcmin": 0.5}


class _Pred:
    def __init__(self, name):
        self.name, self.needs_training = name, name != "none"

    def trained(self, reference):
        return _Pred(self.name)


def test_a_predictor_closing_later_is_averaged_from_the_no_prediction_closure(monkeypatch):
    starts = {"none": 1, "arma": 3}
    lines = []
    monkeypatch.setattr(closedloop.simulation, "LoopModel", lambda c: "model")
    monkeypatch.setattr(closedloop.training, "run_trained",
                        lambda config, p, duration, **kw: _Result(starts[p.name]))
    monkeypatch.setattr(cr, "_loop_predictor", lambda name, *a, **k: _Pred(name))
    cr.run_all("cfg", 0.25, names=("none", "arma"), log=lines.append)
    arma = next(x for x in lines if "arma:" in x)
    # from frame 1 (2 ms): (0.5 + 0.75 + 1.0) / 3 = 0.750; its own window would read 1.000
    assert "SR peak 0.750 (mean from 2 ms, the no-prediction run's closure)" in arma
    assert "(from its own closure at 4 ms)" in arma
