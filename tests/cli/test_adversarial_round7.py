"""Round 7 of issue 27's adversarial inputs (command lines): the ones that failed, fixed.

The full list of inputs tried (id | input | expected | observed | verdict | fix) is in
docs/ADVERSARIAL.md, section "Round 7, issue 27".

Reference: the dispatcher's documented contract (``modalinfo.common.cli.dispatch``: the
subcommand's exit status, one line on stderr and status 2 for an input error, never a
traceback), and Python's own ``print``, which discards what it would write to a closed
stream (``sys.stdout is None`` after ``cmd >&-``).
"""

from __future__ import annotations

import sys

import pytest

from .conftest import exit_code


@pytest.fixture
def small_log(make_small_log):
    return make_small_log(200)


def test_info_with_stdout_closed_exits_0_without_a_traceback(small_log, monkeypatch):
    # e28: `modalinfo info small.npz >&-` stopped on None.write (AttributeError traceback)
    monkeypatch.setattr(sys, "stdout", None)
    assert exit_code(["info", small_log]) == 0


def test_bad_option_with_stderr_closed_still_exits_2(small_log, monkeypatch):
    # e65: `modalinfo info small.npz --bogus 2>&-` exited 1, not the usage status 2
    monkeypatch.setattr(sys, "stderr", None)
    assert exit_code(["info", small_log, "--bogus"]) == 2


def test_an_input_error_with_stdout_closed_is_still_status_2(tmp_path, monkeypatch, capsys):
    # the refusal keeps its status and its one line when only stdout is closed
    monkeypatch.setattr(sys, "stdout", None)
    assert exit_code(["info", tmp_path / "missing.npz"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "missing.npz" in err[0]
