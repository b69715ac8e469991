"""Batch refuses, before any task, ``--set`` values that failed or did nothing after the work.

Round 39 PART b (the command lines): S15 / S41 (``ordering.seeds=[0,0]`` / ``[5]``: every
log an error row after its work, exit 1, in the API's words `seeds`), S05 / S38
(``fitting_error.orderings=zernike:pca`` / ``kl-theory:pca``: the same, with the advice
"Use KLBasis.from_data(zbasis, coeffs)"), S03 / S36 / S37 (``ordering.seeds`` with a
method that draws no samples or with no stability at all, ``ordering.windows`` with pca:
accepted, used by nothing, recorded in the params), S09
(``forecast.predictors=linear,linear``: one column set, the second silently dropped) and
S35 (``--outliers drop --set forecast.outliers=warn`` refused, though ``--set`` wins for
its analysis).

References: ``ordering_stability``'s own rules (at least 2 distinct seeds,
modalinfo/ordering/stability.py), the order and stability the batch row computes
(modalinfo/batch/analyses.py ``_ordering``: stability only for windows >= 2 and a method
other than pca, across seeds only for an MI method), ``ordering.method=pca``'s refusal
on a model basis (round 37 B12) and the README ("2 for an input error found before any
work (a bad ``--set`` value ...)").
"""

from __future__ import annotations

import pytest

import modalinfo.batch
from modalinfo.batch.analyses import resolve_params
from modalinfo.cli import main


@pytest.mark.parametrize("seeds, words", [([0, 0], "distinct"), ([5], "at least 2"),
                                          ([3, 1, 3], "distinct")])
def test_seeds_ordering_stability_refuses_are_refused_up_front(seeds, words):
    with pytest.raises(ValueError, match=rf"ordering\.seeds must .*{words}"):
        resolve_params("ordering", {"seeds": seeds})


@pytest.mark.parametrize("params, first", [
    ({"method": "variance", "seeds": [4, 5]}, "ordering.seeds applies to the MI methods"),
    ({"method": "standard", "seeds": [4, 5]}, "ordering.seeds applies to the MI methods"),
    ({"windows": 0, "seeds": [3, 4]}, "ordering.seeds sets the seed stability"),
    # pca draws no samples: the MI-only guard (fix38-e) speaks before the stability one
    ({"method": "pca", "basis": "kl-data", "seeds": [3, 4]},
     "ordering.seeds applies to the MI methods"),
    ({"method": "pca", "basis": "kl-data", "windows": 8}, "ordering.windows sets"),
])
def test_stability_parameters_nothing_uses_are_refused(params, first):
    with pytest.raises(ValueError) as exc:
        resolve_params("ordering", params)
    assert str(exc.value).startswith(first) and str(exc.value).endswith("drop it")


def test_what_the_stability_uses_is_accepted():
    assert resolve_params("ordering", {"seeds": [3, 4]})["seeds"] == [3, 4]
    assert resolve_params("ordering", {"method": "mi_marginal", "seeds": [0, 9]})["seeds"]
    assert resolve_params("ordering", {"method": "variance", "windows": 8})["windows"] == 8
    assert resolve_params("ordering", {"method": "pca", "basis": "kl-data"})["method"] == "pca"


@pytest.mark.parametrize("orderings, bad", [("zernike:pca", "zernike:pca"),
                                            ("zernike:standard,kl-theory:pca", "kl-theory:pca")])
def test_pca_on_a_model_basis_in_the_orderings_is_refused_up_front(orderings, bad):
    with pytest.raises(ValueError) as exc:
        resolve_params("fitting_error", {"orderings": orderings})
    message = str(exc.value)
    # one guard for every caller (refuse_unused_arguments, fixes 38-b / 38-e)
    assert message.startswith(f"fitting_error.orderings {bad}: pca orders an empirical")
    assert "KLBasis" not in message and "kl-data:pca" in message
    # the default orderings hold kl-data:pca, which is right
    assert resolve_params("fitting_error", {})["orderings"].endswith("kl-data:pca")


def test_a_predictor_named_twice_is_refused():
    with pytest.raises(ValueError, match="names 'linear' twice"):
        resolve_params("forecast", {"predictors": "linear,arma,linear"})
    assert resolve_params("forecast", {"predictors": "linear,arma"})["predictors"]


def test_outliers_drop_with_forecast_own_policy_reaches_the_analyses(tmp_path, monkeypatch,
                                                                     capsys):
    seen = {}

    def fake(inputs, analyses, out, params=None, **kwargs):
        seen.update(params)
        raise ImportError("stop here")  # the command words an ImportError in one line

    monkeypatch.setattr(modalinfo.batch, "analyse_archive", fake)
    log = tmp_path / "a.npy"
    log.write_bytes(b"")
    code = main(["batch", str(log), "--out", str(tmp_path / "out"), "--analyses",
                 "summary,forecast", "--outliers", "drop", "--set", "forecast.outliers=warn",
                 "--quiet"])
    assert code == 2 and "stop here" in capsys.readouterr().err
    assert seen == {"summary": {"outliers": "drop"}, "forecast": {"outliers": "warn"}}
    # without forecast's own policy, drop is still refused before any work
    seen.clear()
    assert main(["batch", str(log), "--out", str(tmp_path / "out2"), "--analyses",
                 "summary,forecast", "--outliers", "drop", "--quiet"]) == 2
    assert not seen and "breaks the time axis" in capsys.readouterr().err


@pytest.mark.parametrize("analysis", ["ordering", "fitting_error"])
def test_too_few_pupil_pixels_named_as_the_batch_parameter(tmp_path, analysis):
    # round 39 PART b, N13: a log of modes up to Z2001 (radial order 62, so at least
    # 2 x 62 = 124 pixels across, Noll's indexing by hand) with the default 64 pixels
    import numpy as np

    from modalinfo.batch.analyses import run_log_task
    from modalinfo.io import save
    from modalinfo.telemetry.log import ModalLog

    x = np.random.default_rng(1).standard_normal((300, 2))
    save(ModalLog(x, rate=100.0, modes=[2, 2001]), tmp_path / "a.npz")
    payload = {"path": str(tmp_path / "a.npz"), "fmt": None, "hints": {},
               "analysis": analysis, "params": resolve_params(analysis, {})}
    with pytest.raises(ValueError) as exc:
        run_log_task(payload)
    assert str(exc.value).startswith(f"{analysis}.pupil_pixels must be >= 124")


def test_outliers_no_analysis_takes_is_refused(tmp_path, capsys):
    # every analysis sets its own policy: --outliers acts on none (S10 after the S35 fix)
    code = main(["batch", str(tmp_path / "a.npy"), "--out", str(tmp_path / "out"),
                 "--analyses", "forecast", "--outliers", "drop", "--set",
                 "forecast.outliers=warn", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "--outliers drop applies to no analysis" in err
    assert "forecast.outliers" in err and len(err.strip().splitlines()) == 1
