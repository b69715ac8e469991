"""``modalinfo forecast --max-seconds S`` with no predictor whose fits are estimated is refused.

Round 49 PART b, X31b: ``forecast t1e5.npz --predictors nn --max-seconds 5`` ran to the end
(44 s of CPU) without a word: only the ARMA predictors estimate their fits
(``Predictor.fit_seconds``: the base returns 0, as ``--help`` says "the ARMA predictors'
are estimated"), so the bound read nothing. Reference: the help text and the base class's
documented 0. With ARMA among the predictors the option keeps working (refused here by
its own rule: a bound below the estimate).
"""

from __future__ import annotations

import numpy as np

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry.log import ModalLog


def _log(path):
    x = np.random.default_rng(0).normal(size=(400, 3)) * 0.1
    save(ModalLog(x, modes=[2, 3, 4], units="rad", rate=1000.0), path)
    return str(path)


def test_max_seconds_without_an_estimated_predictor_is_refused(tmp_path, capsys):
    log = _log(tmp_path / "log.npz")
    code = main(["forecast", log, "--predictors", "linear", "--max-seconds", "5",
                 "--horizon", "1", "--out", str(tmp_path / "o"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert "--max-seconds" in err and "--predictors linear has none" in err, err
    assert not (tmp_path / "o").exists()


def test_max_seconds_with_arma_is_its_own_bound(tmp_path, capsys):
    log = _log(tmp_path / "log.npz")
    code = main(["forecast", log, "--predictors", "arma", "--max-seconds", "1e-9",
                 "--horizon", "1", "--out", str(tmp_path / "o"), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "has none" not in err, err
