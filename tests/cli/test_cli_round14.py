"""Adversarial round 14, PART b (follow the advice): the fixed command-line rows.

Reference, outside the code under test: the command line's own ``--help`` (the flags
``select`` accepts, read from its argparse parser) and a second run that does what the
refusal says, which must be accepted. Rows of docs/ADVERSARIAL.md "Round 14 PART b".
Each test fails on the code before its fix.
"""

from __future__ import annotations

import re

import pytest

from modalinfo.cli import build_parser, main

from .conftest import exit_code


# a random-walk / smooth test log: its lagged MI holds < 20 effective samples, which
# select_inputs warns since fixes 40-a (the effective-sample rule); not this test's point
# ------------------- A05: select's cost refusal named Python arguments (max_lag, ...)
@pytest.mark.filterwarnings("ignore::modalinfo.information.methods.BiasRuleWarning")
def test_select_cost_refusal_advises_flags_that_exist(make_small_log, capsys):
    path = make_small_log(1000)
    argv = ["select", path, "--target", "Z2", "--method", "ksg", "--surrogates", "19",
            "--no-intervals", "--max-seconds", "0.0001"]
    assert exit_code(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    advice = err[0].split("; use ", 1)[1]
    assert "max_lag" not in advice and "candidates='radial'" not in advice
    assert "n_surrogates" not in advice and "method='gaussian'" not in advice
    select = next(a for a in build_parser()._subparsers._group_actions[0].choices.items()
                  if a[0] == "select")[1]
    known = {s for action in select._actions for s in action.option_strings}
    flags = set(re.findall(r"--[\w-]+", advice))
    assert flags >= {"--method", "--max-lag", "--candidates", "--surrogates", "--max-seconds"}
    assert flags <= known
    # doing what it says: --method gaussian is accepted under the same --max-seconds
    assert main(["select", str(path), "--target", "Z2", "--method", "gaussian",
                 "--surrogates", "19", "--no-intervals", "--max-seconds", "0.0001"]) == 0
