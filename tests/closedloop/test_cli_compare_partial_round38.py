"""``closedloop compare`` with some predictors not run exits 1, as ``sweep`` does.

Adversarial round 38 PART b, row H47 (cause W1): ``closedloop compare --preset kaos
--duration 0.01`` printed "not run" for linear, arma and nn-paper (too few frames after
the loop closure to train them) and exited 0 with nothing on stderr. The reference is
the package's own exit-status contract for the same failure: ``closedloop sweep`` exits
1 when one run of a grid failed (its ``--help``: "exit 1 when some run failed"; row E08),
and ``compare`` already exits 1 when none of its predictors ran.
"""

from closedloop.cli import main


def test_compare_with_one_predictor_not_run_exits_1_naming_it(capsys):
    # 20 frames of kaos: none runs, linear has too few frames after closure to train
    code = main(["compare", "--preset", "kaos", "--predictors", "none,linear",
                 "--duration", "0.01", "--quiet"])
    captured = capsys.readouterr()
    assert code == 1
    assert captured.out.count("not run:") == 1 and "\nnone " in captured.out
    assert captured.err.count("\n") == 1
    assert "1 of 2 predictors did not run (linear; first reason:" in captured.err
