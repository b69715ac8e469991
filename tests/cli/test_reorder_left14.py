"""Leftovers 14-misc (issue 27): the command line says an ordering's time in its own flags.

Reference, outside the code under test: the flags each command accepts, read from its
argparse parser (every flag the note advises must exist there), as round 14 PART b's
fix of ``select --max-seconds`` (row A05). The estimate is replaced by a stated number
(monkeypatched), so that the note does not depend on the machine. No timing is asserted.
"""

from __future__ import annotations

import re

import pytest

from modalinfo.cli import build_parser
from modalinfo.ordering import cost

from .conftest import exit_code


def _flags(command):
    parser = dict(build_parser()._subparsers._group_actions[0].choices.items())[command]
    return {s for action in parser._actions for s in action.option_strings}


@pytest.mark.parametrize("command, extra", [
    ("reorder", ["--method", "mi_marginal", "--resamples", "0"]),
    ("fitting-error", ["--orderings", "zernike:mi_marginal"]),
])
def test_an_ordering_over_a_minute_is_noted_in_flags(make_small_log, capsys, monkeypatch,
                                                     command, extra):
    # before: the library's warning, naming `sample_budget`, `n_resamples` and
    # order_modes(...) (an error under the suite's warning filter: exit 2)
    path = make_small_log(200)
    monkeypatch.setattr(cost, "least_ordering_seconds", lambda *a, **k: (90.0, 7))
    argv = [command, path, "--budget", "500", "--pupil-pixels", "16", *extra]
    assert exit_code(argv) == 0
    err = capsys.readouterr().err
    notes = [line for line in err.splitlines() if "estimated at" in line]
    assert len(notes) == 1
    assert notes[0].startswith(f"modalinfo {command}: note: ")
    assert "90 s of CPU" in notes[0]
    for word in ("sample_budget", "n_resamples", "order_modes", "`"):
        assert word not in err
    advised = set(re.findall(r"--[\w-]+", notes[0].split("; ", 1)[1]))
    assert {"--budget", "--estimator"} <= advised <= _flags(command)


def test_fitting_errors_refusal_names_only_its_flags(make_small_log, capsys, monkeypatch):
    # before: "fewer --resamples, a longer --stability window": fitting-error has neither
    path = make_small_log(200)
    monkeypatch.setattr(cost, "least_ordering_seconds", lambda *a, **k: (7200.0, 7))
    argv = ["fitting-error", path, "--budget", "500", "--pupil-pixels", "16",
            "--orderings", "zernike:mi_marginal"]
    assert exit_code(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    advised = set(re.findall(r"--[\w-]+", err[0].split("; use", 1)[1]))
    assert "--budget" in advised and advised <= _flags("fitting-error")
