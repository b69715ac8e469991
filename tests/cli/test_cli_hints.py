"""Analysis commands read foreign logs with the same hint options as ``info``.

Reference: a plain CSV of numbers (what another observatory's software writes) must be
usable by ``reorder``, ``fitting-error`` and ``forecast`` once the user states what the
file lacks; the hints must reach ``modalinfo.io.load`` unchanged.
"""

import numpy as np
import pytest

from modalinfo.cli import main


@pytest.fixture
def foreign_csv(tmp_path):
    path = tmp_path / "foreign.csv"
    rng = np.random.default_rng(0)
    np.savetxt(path, np.cumsum(rng.standard_normal((600, 4)), axis=0) * 0.01, delimiter=",")
    return path


def test_reorder_uses_column_hints(foreign_csv, capsys):
    assert main(["reorder", str(foreign_csv), "--in-modes", "4-7", "--rate", "1000",
                 "--method", "variance", "--pupil-pixels", "16"]) == 0
    out = capsys.readouterr().out
    assert all(label in out for label in ("Z4", "Z5", "Z6", "Z7"))
    assert "Z2" not in out


def test_forecast_hint_and_selection_are_distinct(foreign_csv, capsys):
    # --in-modes says what the columns are; --modes selects among them
    assert main(["forecast", str(foreign_csv), "--in-modes", "4-7", "--modes", "5,6",
                 "--predictors", "linear", "--horizon", "2"]) == 0
    capsys.readouterr()  # a success may note assumed values on stderr
    assert main(["forecast", str(foreign_csv), "--in-modes", "4-7", "--modes", "2",
                 "--predictors", "linear", "--horizon", "2"]) == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_bad_hint_is_one_line(foreign_csv, capsys):
    assert main(["fitting-error", str(foreign_csv), "--in-modes", "2-3"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("modalinfo fitting-error: error:")
