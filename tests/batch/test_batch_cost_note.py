"""A batch task does not pass on the library's note on a long ordering.

Reference: the batch settings' names (``ordering.budget``), which ``OrderingCostWarning``
(worded in ``order_modes``' argument names, ``sample_budget``) does not use; the suite
turns warnings into errors, so a task that lets the note through fails. The note's
threshold is lowered to 0 s so that a tiny log's ordering crosses it.
"""

from __future__ import annotations

import warnings

import pytest

from modalinfo.batch.analyses import resolve_params, run_log_task
from modalinfo.ordering import cost


@pytest.fixture
def tiny_log(tmp_path, helpers):
    from modalinfo.io import save

    path = tmp_path / "log.npz"
    save(helpers.make_log(0), path)
    return path


def test_the_library_notes_this_ordering(tiny_log, monkeypatch):
    # the control: with the threshold at 0 s the library itself warns on this ordering
    from modalinfo.io import load
    from modalinfo.ordering import order_modes
    from modalinfo.ordering.compare import basis_for_log

    monkeypatch.setattr(cost, "NOTE_ORDERING_SECONDS", 0.0)
    log = load(tiny_log)
    with pytest.warns(cost.OrderingCostWarning, match="sample_budget"):
        order_modes(log, basis_for_log("zernike", log, n_pixels=16), "mi_marginal",
                    estimator="gaussian", sample_budget=3000, seed=0, n_resamples=0)


def test_a_batch_ordering_task_keeps_the_note_to_itself(tiny_log, monkeypatch):
    monkeypatch.setattr(cost, "NOTE_ORDERING_SECONDS", 0.0)
    params = resolve_params("ordering", {"budget": 3000, "pupil_pixels": 16, "windows": 2,
                                         "seeds": [0, 1], "estimator": "gaussian",
                                         "method": "mi_marginal", "resamples": 0})
    payload = {"path": str(tiny_log), "fmt": None, "hints": {}, "analysis": "ordering",
               "params": params}
    with warnings.catch_warnings():
        warnings.simplefilter("error", cost.OrderingCostWarning)
        row = run_log_task(payload)
    assert row["first_mode"] == row["order"].split()[0]
