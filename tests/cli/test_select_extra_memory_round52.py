"""``modalinfo select --extra``: the first refusal's figure is what the command needs (fix52-c).

docs/ADVERSARIAL.md, "Stop 57's small items (fix51-c)" item 1, "Left": without
``--extra`` the later ``--max-lag`` check no longer counts LOG's candidate columns again,
but with ``--extra`` it still ran after both quality passes, counting every column
against a figure that had lost the address space the passes leave mapped.

Reference: the kernel's own accounting, as tests/cli/test_memory_refusal_figure_round50.py
(whose helpers this file imports): the command runs in a child under ``RLIMIT_AS``; from
its first refusal "needs about X ... and Y is available" under the limit L0, the limit at
which that check passes is ``L* = L0 + X - Y``. 3 % above ``L*`` the command must run to
exit 0; 2 % below it must be refused before any work, on one line, exit 2. And in
process (the available figure held fixed): at the first figure every later check passes.
"""

from __future__ import annotations

import numpy as np
import pytest

from .test_memory_refusal_figure_round50 import _first_figure, _run, _threshold

pytest.importorskip("resource")

_ARGV = ["select", "log.npy", "--extra", "extra.npy", "--rate", "1000", "--in-units", "rad",
         "--target", "Z2", "--max-lag", "1", "--surrogates", "19", "--no-intervals",
         "--method", "gaussian"]


@pytest.fixture(scope="module")
def two_logs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fig52")
    rng = np.random.default_rng(5212)
    np.save(folder / "log.npy", rng.standard_normal((20_000, 6)))
    np.save(folder / "extra.npy", rng.standard_normal((20_000, 6)))
    return folder


def test_select_extra_runs_just_above_its_first_refusal(two_logs):
    threshold, need = _threshold(_ARGV, two_logs)
    assert need > 30 * 2**20, need  # the passes' figure, not the copies alone
    proc = _run(_ARGV, int(1.03 * threshold), two_logs)
    assert proc.returncode == 0, proc.stderr
    proc = _run(_ARGV, int(0.98 * threshold), two_logs)
    assert proc.returncode == 2 and "needs about" in proc.stderr, proc.stderr
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr


def test_select_extra_at_the_first_figure_every_later_check_passes(two_logs, monkeypatch):
    from modalinfo.cli import main, shared

    monkeypatch.chdir(two_logs)
    monkeypatch.setattr(shared, "memory_available", lambda: 1.0)
    figure = _first_figure(monkeypatch, _ARGV)
    monkeypatch.setattr(shared, "memory_available", lambda: figure * 1.001)
    assert main(_ARGV) == 0
