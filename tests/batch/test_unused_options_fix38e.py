"""The two leftovers of the ordering-option guard (round 37 PART b, fix38-e).

1. ``fitting-error --orderings zernike:pca`` (or ``kl-theory:pca``) and batch ``--set
   fitting_error.orderings=zernike:pca`` were not refused up front: the guard checked
   the basis of a single method only, so the pair failed after reading the log and
   ordering it, with the API's Python remedy ("Use KLBasis.from_data") in the command
   line's words (fitting-error) or as an error row per log (batch).
2. batch ``--set ordering.seeds=[...]`` with a method that draws no samples (variance,
   standard, pca) ran, and its row said the seeds were "not assessed"; with
   ``ordering.windows`` < 2 there are no stability columns for the seeds to act on.

References: ``reorder``'s refusal of ``--method pca --basis zernike`` (the same
remedy: the data K-L, or variance); the library itself: ``compare_orderings`` on a
``zernike:pca`` pair raises after the work ("Use KLBasis.from_data"), and
``order_modes(..., "variance", seed=s)`` gives one order for every seed (numpy's
mean-square argsort), so a list of seeds can change nothing. ``reorder`` has no
``--seeds``: its ``--stability`` uses seeds 0-2 by default and says "not assessed" for
variance, which batch still does for its default seeds (not given).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.batch.analyses import resolve_params
from modalinfo.cli import main

PCA = ("{where} {basis}:pca: pca orders an empirical K-L basis of the same log; {basis} is "
       "not one: use kl-data:pca, or {basis}:variance")
SEEDS = ("ordering.seeds applies to the MI methods (mi_greedy, mi_marginal); "
         "ordering.method {method} uses none: drop it")


@pytest.mark.parametrize("orderings, basis", [
    ("zernike:pca", "zernike"), ("kl-theory:pca", "kl-theory"),
    ("zernike:standard,kl-data:pca,kl-theory:pca", "kl-theory"),
])
def test_batch_pca_pair_on_a_model_basis_is_refused(orderings, basis):
    with pytest.raises(ValueError) as exc:
        resolve_params("fitting_error", {"orderings": orderings})
    assert str(exc.value) == PCA.format(where="fitting_error.orderings", basis=basis)


def test_batch_pca_on_the_data_kl_is_accepted():
    assert resolve_params("fitting_error", {"orderings": "kl-data:pca"})["orderings"] \
        == "kl-data:pca"
    # the default orderings hold kl-data:pca
    assert "kl-data:pca" in resolve_params("fitting_error")["orderings"]


@pytest.mark.parametrize("orderings, basis", [
    ("zernike:pca", "zernike"), ("zernike:variance,kl-theory:pca", "kl-theory"),
])
def test_fitting_error_command_refuses_before_reading_the_log(tmp_path, capsys, orderings,
                                                              basis):
    # a log that does not exist: the refusal comes before it is read
    assert main(["fitting-error", str(tmp_path / "absent.npz"), "--orderings",
                 orderings]) == 2
    err = capsys.readouterr().err
    assert err == "modalinfo fitting-error: error: " + PCA.format(
        where="--orderings", basis=basis) + "\n"


def test_the_pair_fails_in_the_library_after_the_work(folder):
    # the reference: zernike:pca cannot run on this log (correlated Zernike coefficients)
    from modalinfo.io import load
    from modalinfo.ordering.compare import compare_orderings

    with pytest.raises(ValueError, match="KLBasis.from_data"):
        compare_orderings(load(folder / "a.npz"), [("zernike", "pca")], n_pixels=32)


def test_batch_command_refuses_a_pca_pair_before_any_task(folder, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["batch", str(folder), "--analyses", "fitting_error", "--out", str(out),
                 "--set", "fitting_error.orderings=zernike:pca", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err == "modalinfo batch: error: " + PCA.format(
        where="fitting_error.orderings", basis="zernike") + "\n"
    assert not out.exists()


@pytest.mark.parametrize("method", ["variance", "standard", "pca"])
def test_batch_seeds_with_a_method_without_mi_are_refused(method):
    params = {"method": method, "seeds": [3, 4]}
    if method == "pca":
        params["basis"] = "kl-data"
    with pytest.raises(ValueError) as exc:
        resolve_params("ordering", params)
    assert str(exc.value) == SEEDS.format(method=method)


def test_batch_seeds_without_windows_are_refused():
    with pytest.raises(ValueError) as exc:
        resolve_params("ordering", {"method": "mi_marginal", "windows": 0, "seeds": [3, 4]})
    # the words of _refuse_unused_stability (round 39 PART b, S36), one rule for seeds and
    # windows
    assert str(exc.value) == ("ordering.seeds sets the seed stability; ordering.windows 0 "
                              "assesses no stability (it takes >= 2): drop it")


def test_batch_seeds_accepted_where_they_act_and_defaults_untouched():
    assert resolve_params("ordering", {"method": "mi_marginal", "seeds": [3, 4]})["seeds"] \
        == [3, 4]
    # not given: the default seeds, as reorder --stability's seeds 0-2 (row: not assessed)
    assert resolve_params("ordering", {"method": "variance"})["seeds"] == [0, 1, 2]


def test_batch_command_refuses_seeds_before_any_task(folder, tmp_path, capsys):
    from modalinfo.bases import Pupil, ZernikeBasis
    from modalinfo.io import load
    from modalinfo.ordering import order_modes

    out = tmp_path / "out"
    assert main(["batch", str(folder), "--analyses", "ordering", "--out", str(out),
                 "--set", "ordering.method=variance", "--set", "ordering.seeds=[3,4]",
                 "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err == "modalinfo batch: error: " + SEEDS.format(method="variance") + "\n"
    assert not out.exists()
    # the reference: the seeds can change nothing: one variance order, numpy's argsort
    log = load(folder / "a.npz")
    basis = ZernikeBasis(Pupil(32), range(2, 8))
    orders = {tuple(order_modes(log, basis, "variance", seed=s).labels) for s in (3, 4)}
    assert orders == {tuple(f"Z{j}" for j in 2 + np.argsort(-np.mean(
        np.asarray(log.coeffs) ** 2, axis=0), kind="stable"))}
