"""Round 35 PART b, Q17 and E01: what the user typed or wrote, named as typed.

Reference: the inputs themselves - a negative ``--train`` is neither a fraction in
(0, 1) nor a number of frames (it was read as a fraction: "-10000 of the 2000"), and a
CSV cell written as numpy 2's scalar repr ``np.float64(0.5)`` is that text, not the
number 0.5 the command line's repr rewrite showed in its place.
"""

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


@pytest.mark.parametrize("train", ["-5", "-0.5", "0"])
def test_forecast_refuses_a_train_that_is_not_positive(tmp_path, capsys, train):
    path = tmp_path / "log.npz"
    x = np.cumsum(np.random.default_rng(0).standard_normal((400, 2)), axis=0)
    save(ModalLog(x, rate=1000.0, modes=[2, 3], units="rad"), path)
    code = main(["forecast", str(path), "--predictors", "linear", f"--train={train}"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert f"--train must be a fraction in (0, 1) or a number of frames >= 2; got {train}" \
        in err
    assert "of the 400" not in err


def test_numpy_repr_cells_are_named_as_written(tmp_path, capsys):
    path = tmp_path / "reprs.csv"
    path.write_text("Z2,Z3\nnp.float64(0.5),np.float64(0.25)\nnp.float64(0.1),"
                    "np.float64(0.2)\n")
    code = main(["info", str(path)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "'np.float64(0.5)'" in err and "numpy scalar repr" in err
    assert "string '0.5'" not in err
