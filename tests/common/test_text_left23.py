"""Tables aligned by terminal display width: wide characters and combining marks.

Reference: the Unicode Character Database as published (EastAsianWidth.txt and the
general categories of UnicodeData.txt, Unicode 15): U+65E5 and U+672C (CJK ideographs),
U+50BE / U+304D, U+D55C (a Hangul syllable) and U+1F600 (an emoji, since Unicode 9) are
East Asian Width W, U+FF21 / U+FF22 (fullwidth A, B) are F, U+00BD is A (ambiguous:
one column, as wcwidth and glibc count it), U+0301 and U+0303 are combining marks
(category Mn), U+200D (zero-width joiner) is Cf, and U+1161 / U+11AB are Hangul medial
and final jamo, so the NFD form of U+D55C takes the same two columns as its NFC form.
The widths below are written by hand from those tables, never from the code under test.
Leftovers 23-misc (issue 27): before, ``modalinfo info`` padded labels by code points, so
a row holding a CJK or emoji label ended 2 columns right of the header and a row with a
combining mark 1 column left.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.common.text import display_width, pad
from modalinfo.io import save
from modalinfo.ordering.result import OrderingResult
from modalinfo.telemetry.log import ModalLog

from ..cli.conftest import exit_code

#: text -> terminal columns, from the Unicode tables (module docstring)
KNOWN = {
    "Z12": 3,
    "\u65e5\u672c": 4,            # two CJK ideographs (W)
    "\uff21\uff22": 4,            # fullwidth A B (F)
    "\U0001f600": 2,              # an emoji (W)
    "e\u0301": 1,                 # e + combining acute (Mn)
    "Z\u03032": 2,                # Z + combining tilde, then 2
    "a\u200db": 2,                # a, zero-width joiner (Cf), b
    "\u00bd": 1,                  # one half (A: ambiguous, one column)
    "\ud55c": 2,                  # Hangul syllable (W)
    "\u1112\u1161\u11ab": 2,      # its NFD: leading jamo (W) + medial + final (0)
    "": 0,
}


@pytest.mark.parametrize("text", list(KNOWN))
def test_display_width_known(text):
    assert display_width(text) == KNOWN[text]


def test_pad_by_display_width():
    for text, width in KNOWN.items():
        left, right = pad(text, 8), pad(text, 8, ">")
        assert left == text + " " * (8 - width) and right == " " * (8 - width) + text
    assert pad("\u65e5\u672c\u65e5", 4) == "\u65e5\u672c\u65e5"  # wider: never cut
    with pytest.raises(ValueError, match="`align` must be"):
        pad("x", 3, "^")


LABELS = ["tip", "\u50be\u304d", "Z\u03032", "\U0001f600foc"]
LABEL_WIDTHS = [3, 4, 2, 5]  # by hand: ASCII 1, W 2, Mn 0


def test_info_table_aligned(tmp_path, capsys):
    rng = np.random.default_rng(0)
    coeffs = np.cumsum(rng.standard_normal((400, 4)), axis=0) * 0.01
    save(ModalLog(coeffs, rate=2000.0, modes=LABELS, convention="labels", units="rad"),
         tmp_path / "wide.npz")
    assert exit_code(["info", tmp_path / "wide.npz"]) == 0
    lines = capsys.readouterr().out.splitlines()
    head = next(ln for ln in lines if ln.startswith("mode ") and "lag1" in ln)
    end = len(head.split("   [")[0])  # the column where "lag1" ends (ASCII header)
    rows = lines[lines.index(head) + 1:lines.index(head) + 5]
    for label, width, row in zip(LABELS, LABEL_WIDTHS, rows, strict=True):
        assert row.startswith(label)
        # the label's columns plus the ASCII rest: every row ends under "lag1"
        assert width + len(row) - len(label) == end, row


def test_ordering_table_aligned():
    res = OrderingResult(order=np.array([1, 0, 2, 3]), labels=tuple(LABELS[i] for i in
                         (1, 0, 2, 3)), basis_labels=tuple(LABELS), method="standard")
    lines = res.table().splitlines()
    # "step" (5) + 2 spaces + the 8-column mode cell: each row is 15 columns
    widths = [3, 4, 2, 5]
    for s, row in enumerate(lines[1:]):
        label = res.labels[s]
        assert width_of(row, label, widths[LABELS.index(label)]) == 15, row


def width_of(row: str, label: str, label_width: int) -> int:
    """Columns of a row whose only non-ASCII text is ``label`` (of known width)."""
    assert label in row
    return label_width + len(row) - len(label)
