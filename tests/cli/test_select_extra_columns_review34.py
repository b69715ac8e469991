"""select's candidate search is checked on LOG's and --extra's columns (review34, round 34).

``cmd_select.run`` checks the candidate search's working arrays on every candidate
column: with ``--extra`` they are LOG's modes and LOG2's, each at ``--max-lag`` lags.
Since fix52-c the command's one check before any quality pass counts them all, with
both logs' ``LOG_COPIES`` copies (stop 58, fix51-c: LOG's columns there, --extra's
again in a second check after both passes, which then read the address space the passes
leave mapped as used). Reference: the count by hand ((3 + 2) modes x 4 lags = 20
columns, and (3 + 1) x 1 = 4; 400 frames, ``search_bytes`` (float64 copies and blocks) of the
columns, ``LOG_COPIES`` of each log's 400 x modes coefficients), against the figure
handed to ``check_command_memory`` (recorded, then passed on); no later check of them.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.cli import cmd_select
from modalinfo.cli.shared import LOG_COPIES
from modalinfo.information.selection import search_bytes
from modalinfo.io import save
from modalinfo.telemetry import ModalLog

from .conftest import exit_code


@pytest.mark.parametrize("n_extra, lags", [(2, 4), (1, 1)])
def test_the_second_check_counts_the_extra_logs_columns(tmp_path, monkeypatch, n_extra, lags):
    rng = np.random.default_rng(34)
    t = np.arange(400) / 1000.0
    log = save(ModalLog(rng.standard_normal((400, 3)), timestamps=t, modes=[2, 3, 4],
                        units="rad"), tmp_path / "a.npz")
    extra = save(ModalLog(rng.standard_normal((400, n_extra)), timestamps=t,
                          modes=list(range(5, 5 + n_extra)), units="rad"), tmp_path / "b.npz")
    seen, later = [], []
    real, real_later = cmd_select.check_command_memory, cmd_select.check_memory

    def record(own, what, *args, **kwargs):
        seen.append((own, what))
        return real(own, what, *args, **kwargs)

    def record_later(need, what, *args, **kwargs):
        later.append(what)
        return real_later(need, what, *args, **kwargs)

    monkeypatch.setattr(cmd_select, "check_command_memory", record)
    monkeypatch.setattr(cmd_select, "check_memory", record_later)
    assert exit_code(["select", log, "--target", "Z2", "--max-lag", lags, "--extra", extra,
                      "--surrogates", "19"]) == 0
    columns = (3 + n_extra) * lags
    copies = LOG_COPIES * 8 * 400 * (3 + n_extra)
    assert len(seen) == 1
    own, what = seen[0]
    assert own == search_bytes(400 * columns) + copies
    assert f"--max-lag {lags}'s {columns} candidate columns" in what
    assert "a.npz" in what and "b.npz" in what
    assert not [w for w in later if "candidate columns" in w]
