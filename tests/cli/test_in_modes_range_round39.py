"""``--in-modes`` with a range of a trillion modes: a clear refusal, not "out of memory".

Round 39 PART b, S34 / S42: ``modalinfo info raw.npy --in-modes 2-1000000000000`` expanded
the range before anything else and ended in "out of memory: MemoryError; use a smaller
log or smaller options" (batch: "use fewer local workers ..."), advice the user cannot
follow; ``2-30000000`` held 1.5 GB for 42 s before the column count refused it (S43).
Reference: the range's own count (hi - lo + 1, by hand) against the bound
``modalinfo.bases.indexing.MAX_LISTED_MODES``; a list up to the bound is still parsed
(``list(range(...))``).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.bases.indexing import MAX_LISTED_MODES, parse_modes
from modalinfo.cli import main


def test_parse_modes_refuses_a_range_past_the_bound_by_its_count():
    with pytest.raises(ValueError) as exc:
        parse_modes("2-1000000000000", "--in-modes")
    assert str(exc.value).startswith("--in-modes: range '2-1000000000000' names "
                                     "999999999999 modes")
    with pytest.raises(ValueError, match="names 2 modes"):  # the bound counts every entry
        parse_modes(f"1-{MAX_LISTED_MODES - 1},5-6")
    assert parse_modes(f"1-{MAX_LISTED_MODES}") == list(range(1, MAX_LISTED_MODES + 1))


@pytest.mark.parametrize("command", ["info", "batch"])
def test_command_line_says_the_range_not_out_of_memory(tmp_path, capsys, command):
    path = tmp_path / "raw.npy"
    np.save(path, np.random.default_rng(0).standard_normal((64, 3)))
    argv = [command, str(path), "--rate", "100", "--in-modes", "2-1000000000000"]
    if command == "batch":
        argv += ["--out", str(tmp_path / "out"), "--quiet"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "memory" not in err and "range '2-1000000000000' names 999999999999 modes" in err
    assert len(err.strip().splitlines()) == 1
