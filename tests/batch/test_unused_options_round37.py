"""Batch refuses, before any task, what ``reorder`` and ``fitting-error`` refuse.

Round 37 PART b: B04 / B05 (``--set ordering.method=variance`` with
``ordering.resamples=100`` or ``ordering.seed=5`` ran, the params recording them), B08
(``fitting_error.orderings=zernike:variance`` with ``fitting_error.seed=3`` ran), B12
(``ordering.method=pca`` on the default Zernike basis: every log an error row after its
work, with the API's advice "Use KLBasis.from_data"), and B06 (the ordering row of a
method that draws no samples reported ``seed_spearman`` 1.0 and ``seed_top_overlap`` 1,
a stability across seeds that do not act).

References: the refusals of ``reorder`` (``--resamples`` / ``--seed`` with ``--method
variance``; ``--method pca`` on ``--basis zernike``) and ``fitting-error`` (``--seed``
with ``--orderings zernike:variance``), whose messages are unchanged (checked here
word for word); for B06, ``order_modes`` itself: the variance order is the same for
every seed, so no seed agreement is measured, and the row says it in
``StabilityResult.summary``'s words (round 36 R03).
"""

from __future__ import annotations

import math

import pytest

from modalinfo.batch.analyses import resolve_params, run_log_task
from modalinfo.cli import main

RULE = "applies to the MI {noun} (mi_greedy, mi_marginal); {chosen} uses none: drop it"


@pytest.mark.parametrize("param", ["resamples", "seed", "budget", "estimator"])
def test_ordering_parameter_no_method_uses_is_refused(param):
    value = {"resamples": 100, "seed": 5, "budget": 1000, "estimator": "ksg"}[param]
    with pytest.raises(ValueError) as exc:
        resolve_params("ordering", {"method": "variance", param: value})
    assert str(exc.value) == f"ordering.{param} " + RULE.format(
        noun="methods", chosen="ordering.method variance")


def test_what_the_methods_use_is_accepted():
    # --resamples 0 asks for none: what variance does (reorder's rule)
    assert resolve_params("ordering", {"method": "variance", "resamples": 0})["resamples"] == 0
    assert resolve_params("ordering", {"method": "mi_marginal", "seed": 5})["seed"] == 5
    assert resolve_params("ordering", {"method": "pca", "basis": "kl-data"})["method"] == "pca"
    p = resolve_params("fitting_error", {"orderings": "zernike:variance,zernike:mi_greedy",
                                         "seed": 3})
    assert p["seed"] == 3


@pytest.mark.parametrize("basis", ["zernike", "kl-theory"])
def test_pca_on_a_model_basis_is_refused_in_batch_terms(basis):
    params = {"method": "pca"} if basis == "zernike" else {"method": "pca", "basis": basis}
    with pytest.raises(ValueError) as exc:
        resolve_params("ordering", params)
    assert str(exc.value) == (  # one wording with the list's (fold 40-a)
        f"ordering.method pca with ordering.basis {basis}: pca orders an empirical K-L "
        f"basis of the same log; {basis} is not one: use ordering.basis kl-data, or "
        "ordering.method variance")


def test_fitting_error_seed_without_an_mi_ordering_is_refused():
    with pytest.raises(ValueError) as exc:
        resolve_params("fitting_error", {"orderings": "zernike:variance", "seed": 3})
    assert str(exc.value) == "fitting_error.seed " + RULE.format(
        noun="orderings", chosen="fitting_error.orderings zernike:variance")


@pytest.mark.parametrize("settings, start", [
    (["ordering.method=variance", "ordering.resamples=100"], "ordering.resamples applies"),
    (["ordering.method=variance", "ordering.seed=5"], "ordering.seed applies"),
    (["ordering.method=pca"], "ordering.method pca with ordering.basis zernike: pca orders"),
])
def test_batch_command_refuses_before_any_task(folder, tmp_path, capsys, settings, start):
    out = tmp_path / "out"
    argv = ["batch", str(folder), "--analyses", "ordering", "--out", str(out), "--quiet"]
    for item in settings:
        argv += ["--set", item]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"modalinfo batch: error: {start}") and err.count("\n") == 1
    assert not out.exists()  # nothing submitted, nothing written


def test_fitting_error_batch_command_refuses(folder, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["batch", str(folder), "--analyses", "fitting_error", "--out", str(out),
                 "--set", "fitting_error.orderings=zernike:variance",
                 "--set", "fitting_error.seed=3", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("modalinfo batch: error: fitting_error.seed applies")
    assert not out.exists()


def test_ordering_row_of_a_method_without_samples_has_no_seed_agreement(folder):
    from modalinfo.bases import Pupil, ZernikeBasis
    from modalinfo.io import load
    from modalinfo.ordering import order_modes

    payload = {"path": str(folder / "a.npz"), "fmt": None, "hints": {},
               "analysis": "ordering", "params": resolve_params("ordering",
                                                                {"method": "variance"})}
    row = run_log_task(payload)
    assert math.isnan(row["seed_spearman"]) and math.isnan(row["seed_top_overlap"])
    assert row["seed_note"] == ("not assessed (method variance draws no samples: every "
                                "seed gives the same order)")
    assert all(math.isfinite(row[k]) for k in ("window_spearman", "window_kendall",
                                               "window_top_overlap"))
    # the reference: the variance order is one order whatever the seed
    log = load(folder / "a.npz")
    basis = ZernikeBasis(Pupil(32), range(2, 8))
    orders = {tuple(order_modes(log, basis, "variance", seed=s).labels) for s in (0, 1, 2)}
    assert len(orders) == 1
