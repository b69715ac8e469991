"""Round 36 PART b: options that act on nothing here are refused.

References: the documented scope of each option - ``--estimator`` / ``--budget`` /
``--seed`` draw and estimate the MI of the ``mi_*`` orderings, ``--outer-scale`` builds the
``kl-theory`` basis; ``reorder`` refuses the same options with the same methods (rounds
13 / 17 PART b). Before the fixes ``fitting-error`` accepted them and printed the same
table to the digit (F01-F07).
"""

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


@pytest.fixture
def log_path(tmp_path):
    x = np.random.default_rng(36).standard_normal((300, 5)) * 0.1
    path = tmp_path / "log.npz"
    save(ModalLog(x, rate=1000.0, modes=[2, 3, 4, 5, 6], units="rad",
                  wavelength=5e-7), path)
    return path


@pytest.mark.parametrize("extra, orderings, flag", [
    (["--seed", "3"], "zernike:variance", "--seed"),
    (["--estimator", "ksg"], "zernike:standard", "--estimator"),
    (["--budget", "1000"], "zernike:variance", "--budget"),
    (["--outer-scale", "5"], "zernike:variance,zernike:standard", "--outer-scale"),
])
def test_fitting_error_refuses_an_option_no_ordering_uses(log_path, capsys, extra,
                                                          orderings, flag):
    code = main(["fitting-error", str(log_path), "--pupil-pixels", "24", "--orderings",
                 orderings, *extra])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
    assert f"error: {flag} applies to the" in err and "drop it" in err


def test_fitting_error_keeps_them_where_they_act(log_path, capsys):
    code = main(["fitting-error", str(log_path), "--pupil-pixels", "24", "--orderings",
                 "zernike:mi_marginal,kl-theory:variance", "--seed", "3", "--budget",
                 "2000", "--outer-scale", "20"])
    assert code == 0, capsys.readouterr().err

