"""Terminal width of emoji grapheme clusters: ZWJ sequences, VS16, skin tones, flags.

Reference: Unicode UTS #51 (Unicode Emoji, version 15): every sequence below is a
recommended-for-general-interchange (RGI) emoji sequence of emoji-zwj-sequences.txt,
emoji-sequences.txt or emoji-variation-sequences.txt, and UTS #51 sec. 2 / annex A
say an emoji presentation sequence or an RGI sequence is shown as one emoji glyph,
which terminals (and ``wcwidth.wcswidth`` >= 0.2.9: its ZWJ and VS16 rules) put in two
columns; one regional indicator alone is East Asian Width N, one column. The widths
are written by hand from those documents, never from the code under test.
Leftovers 26-kde (issue 27): before, each code point counted alone (the family 6
columns, the red heart 1, a thumbs-up with a skin tone 4), so a label holding one
shifted the columns of a table after it.
"""

from __future__ import annotations

import pytest

from modalinfo.common.text import display_width, pad

#: text -> terminal columns (module docstring)
KNOWN = {
    "\U0001f468\u200d\U0001f469\u200d\U0001f467": 2,  # family: man ZWJ woman ZWJ girl
    "\U0001f469\u200d\u2764\ufe0f\u200d\U0001f468": 2,  # couple with heart (ZWJ + VS16)
    "\U0001f3f3\ufe0f\u200d\U0001f308": 2,  # rainbow flag: white flag VS16 ZWJ rainbow
    "\U0001f9d1\U0001f3fd\u200d\U0001f4bb": 2,  # technologist, medium skin tone
    "\u2764\ufe0f": 2,                      # red heart: text-default base + VS16
    "#\ufe0f\u20e3": 2,                     # keycap number sign
    "\U0001f44d\U0001f3fd": 2,              # thumbs up, medium skin tone
    "\U0001f1eb\U0001f1f7": 2,              # flag of France: two regional indicators
    "\U0001f1eb": 1,                        # one regional indicator alone (N)
    "Z\u2764\ufe0f5": 4,                    # in a label: Z, the heart, 5
    "\U0001f468\u200d\U0001f469\u200d\U0001f467 fam": 6,
}


@pytest.mark.parametrize("text", list(KNOWN))
def test_emoji_cluster_width(text):
    assert display_width(text) == KNOWN[text]


def test_pad_aligns_emoji_labels():
    cells = [pad(text, 10) for text in KNOWN]
    assert all(display_width(c) == 10 for c in cells)
    spaces = [len(c) - len(t) for c, t in zip(cells, KNOWN, strict=True)]
    assert spaces == [10 - w for w in KNOWN.values()]
