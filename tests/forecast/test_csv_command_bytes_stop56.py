"""The forecast CSV's ``command`` cell holds a file name's undecodable byte as ``\\xNN``.

Review 32 found ``modalinfo forecast LOG --out DIR`` refused (exit 2, "'utf-8' codec can't
encode character '\\udce9'") when an argument held a byte that is not UTF-8 (PEP 383 lone
surrogate): the CSV's provenance cell is encoded strictly. Reference: the csv module and
pandas reading the file back as UTF-8, and ``codecs.escape_decode`` of the cell giving the
argument's bytes (``os.fsencode``), as batch rows show a name (``ls -b``'s form).
"""

from __future__ import annotations

import codecs
import csv
import os
import shlex

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, evaluate


@pytest.fixture(scope="module")
def ev():
    x = np.cumsum(np.random.default_rng(56).standard_normal((400, 2)), axis=0)
    return evaluate({"linear": LinearPredictor()}, x, train=200, horizons=[1])


def test_undecodable_argument_is_written_as_escaped_bytes(ev, tmp_path):
    arg = os.fsdecode(b"d\xe9/log.npz")
    command = ["modalinfo", "forecast", arg, "--out", "out"]
    path = ev.to_csv(tmp_path / "ev.csv",
                     provenance={"modalinfo": "x", "command": command,
                                 "input": {"sha256": "0" * 64}})
    with path.open(newline="", encoding="utf-8") as f:  # strict UTF-8 read
        rows = list(csv.DictReader(f))
    cell = rows[0]["command"]
    assert "\\xe9" in cell
    raw = codecs.escape_decode(cell.encode("ascii"))[0]
    assert raw == os.fsencode(shlex.join(command))


def test_plain_command_cell_is_the_shell_line(ev, tmp_path):
    command = ["modalinfo", "forecast", "my log.npz", "--horizons", "1"]
    path = ev.to_csv(tmp_path / "ev.csv", provenance={"command": command})
    with path.open(newline="", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert {r["command"] for r in rows} == {shlex.join(command)}
