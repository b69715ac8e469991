"""``closedloop compare --predictors`` with an empty name is refused before any run.

Round 44 PART b, b31: ``--predictors=persistence,,linear`` ran two predictors, the empty
name dropped without a word (``if n.strip()``), while ``modalinfo forecast --predictors
linear,`` is refused ("unknown predictor ''"). Reference: the option's help, "a comma
list" of the names in ``closedloop.control.predictors.NAMES`` (an empty one is none of
them), and ``modalinfo forecast``'s refusal of the same spelling.
"""
import pytest

from closedloop.cli import main


@pytest.mark.parametrize("text", ["persistence,,linear", "none,", ",none", "none, ,linear"])
def test_empty_name_is_refused(capsys, text):
    code = main(["compare", "--preset", "kaos", "--duration", "0.01",
                 f"--predictors={text}", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2
    assert "has an empty name" in err and err.count("\n") == 1


def test_empty_list_keeps_its_message(capsys):
    assert main(["compare", "--preset", "kaos", "--predictors=", "--quiet"]) == 2
    assert "must be a comma list of" in capsys.readouterr().err
