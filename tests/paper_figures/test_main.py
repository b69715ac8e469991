"""``python -m paper_figures``: refuses to replace outputs unasked; makes every figure.

Reference: the project's rule that no tool overwrites a user's file unasked, and the
report contract of ``paper_figures/__init__.py`` (one section per figure).
"""


import pytest

from paper_figures.__main__ import DEFAULT_LOG, main


def test_shipped_log_exists():
    assert DEFAULT_LOG.is_file()


@pytest.mark.parametrize("name", ["report.md", "fig1_fitting_error.png", "fig1_fitting_error.pdf",
                                  "fig5_forecast.json", "fig5_forecast.pdf"])
def test_refuses_existing_outputs(tmp_path, capsys, name):
    (tmp_path / name).write_text("mine")
    assert main(["--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and name in err and "--overwrite" in err
    assert (tmp_path / name).read_text() == "mine"


def test_missing_log(tmp_path, capsys):
    assert main(["--out", str(tmp_path), "--log", str(tmp_path / "nope.npz")]) == 2
    assert "does not exist" in capsys.readouterr().err
