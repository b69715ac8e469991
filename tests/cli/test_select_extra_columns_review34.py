"""select's candidate search is checked on LOG's and --extra's columns (review34, round 34).

``cmd_select.run`` (stop 58, fix51-c) checks the candidate search's working arrays again
only where they hold more columns than ``_load``'s check of LOG admitted: with ``--extra``
the candidates are LOG's modes and LOG2's, each at ``--max-lag`` lags. Reference: the
count by hand ((3 + 2) modes x 4 lags = 20 columns, and (3 + 1) x 1 = 4, one column more
than LOG's 3; 400 frames, ``_WORKING_COPIES`` float64 copies), against the figure handed
to ``check_memory`` (recorded, then passed on).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.cli import cmd_select
from modalinfo.information.selection import _WORKING_COPIES
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
    seen = []
    real = cmd_select.check_memory

    def record(need, what, *args, **kwargs):
        seen.append((need, what))
        return real(need, what, *args, **kwargs)

    monkeypatch.setattr(cmd_select, "check_memory", record)
    assert exit_code(["select", log, "--target", "Z2", "--max-lag", lags, "--extra", extra,
                      "--surrogates", "19"]) == 0
    search = [(need, what) for need, what in seen if "candidate columns" in what]
    columns = (3 + n_extra) * lags  # one more column than LOG's check admitted, or more
    assert search == [(_WORKING_COPIES * 8 * 400 * columns,
                       f"--max-lag {lags} ({columns} candidate columns x 400 frames)")]
