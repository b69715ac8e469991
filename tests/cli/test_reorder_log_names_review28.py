"""``log_names_note`` spells out twelve modes and counts the rest (review28, round 28).

``cmd_reorder.SHOWN_NAMES`` is 12 ("how many of the ordered modes the log-names line
spells out"); the round 43 test used 10 modes, so planted bugs R28-R1 (11 shown) and
R28-R3 ("... (0 more)" when exactly 12) escaped it. References: the ANSI Z80.28 table by
hand (Noll Z2 = (1, 1) = A2, Z3 = A1, Z4 = A4, Z5 = A3, Z6 = A5, Z11 = (4, 0) = A12) and
the count of labels written here.
"""

import re
from types import SimpleNamespace

import pytest

from modalinfo.cli.cmd_reorder import log_names_note

HAND = {"Z2": "A2", "Z3": "A1", "Z4": "A4", "Z5": "A3", "Z6": "A5", "Z11": "A12"}


@pytest.mark.parametrize("n", [11, 12, 13, 20])
def test_twelve_pairs_and_the_rest_counted(n):
    labels = tuple(f"Z{j}" for j in range(2, 2 + n))
    note = log_names_note(labels, SimpleNamespace(convention="ansi"), "zernike")
    pairs = re.findall(r"(Z\d+) = (A\d+)", note)
    assert [p[0] for p in pairs] == list(labels[:12])
    for noll, own in pairs:
        if noll in HAND:
            assert own == HAND[noll]
    if n > 12:
        assert note.endswith(f", ... ({n - 12} more)")
    else:
        assert "more)" not in note and "..." not in note
