"""Stop 57, fix51-c item 2: batch's quality-pass refusal counts a loaded log once.

Reference: the single command's refusal on the same log
(``modalinfo.cli.shared.check_quality_memory``, fixed in round 50 PART b, M12): the log
read into memory before the check is already missing from the memory available, so
the pass needs ``quality_memory`` (plus a clipped copy under ``clip``), not that plus
the log. batch's ``_check_quality_memory`` added the in-memory log's bytes again and
named a larger figure than ``modalinfo convert`` on the same log (and refused a log
that fits). Both figures are read from the refusals' text, printed by the same
``format_size``; the available memory is patched to 0 B on both sides.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog

_NEEDS = re.compile(r"needs about ([\d.]+ \w+) of memory")


@pytest.mark.parametrize("policy", ["warn", "clip"])
def test_batch_refusal_figure_is_the_single_commands(monkeypatch, policy):
    from modalinfo.batch.analyses import _check_quality_memory
    from modalinfo.cli import shared
    from modalinfo.common import memory
    from modalinfo.telemetry.quality import quality_memory

    # 20,000 x 6 float64 in memory: 0.92 MiB, well above the figures' 0.01 MiB digits
    log = ModalLog(np.random.default_rng(51).standard_normal((20_000, 6)), rate=1000.0,
                   units="rad")
    monkeypatch.setattr(shared, "memory_available", lambda: 0.0)
    with pytest.raises(shared.CommandError) as single:
        shared.check_quality_memory(argparse.Namespace(outliers=policy), log, Path("a.npz"))
    monkeypatch.setattr(memory, "usable_memory_bytes", lambda: 0.0)
    with pytest.raises(MemoryError) as batch:
        _check_quality_memory("a.npz", log, policy)
    figure = _NEEDS.search(str(single.value))[1]
    assert _NEEDS.search(str(batch.value))[1] == figure, (str(batch.value), figure)
    # and the figure is the pass's own (plus the clipped copy), not the log's twice
    expected = quality_memory(20_000, 6) + (log.coeffs.nbytes if policy == "clip" else 0)
    from modalinfo.common.sizes import format_size

    assert figure == format_size(expected)


def test_batch_runs_a_loaded_log_whose_pass_fits(monkeypatch):
    # room for the pass alone (the log is loaded already): no refusal; before the fix
    # the log's 0.92 MiB counted again refused it
    from modalinfo.batch.analyses import _check_quality_memory
    from modalinfo.common import memory
    from modalinfo.telemetry.quality import quality_memory

    log = ModalLog(np.zeros((20_000, 6)), rate=1000.0, units="rad")
    monkeypatch.setattr(memory, "usable_memory_bytes",
                        lambda: quality_memory(20_000, 6) + 1.0)
    _check_quality_memory("a.npz", log, "warn")
