"""Review 21: emoji cluster widths at the ends of the skin-tone block; letters and ZWJ.

References: Unicode UTS #51 (Unicode Emoji 15): the five emoji modifiers are U+1F3FB ..
U+1F3FF (Fitzpatrick types 1-2 to 6), and a base followed by any one of them is one
RGI emoji modifier sequence (emoji-sequences.txt), shown in two columns; UAX #11: CJK
ideographs are East Asian Width W, two columns each, and a ZWJ between two letters is
no emoji ZWJ sequence (UTS #51 sec. 1.4.6: an emoji ZWJ element is an emoji), so it
joins nothing on a terminal: the module notes' ``"a" + ZWJ + "b"`` = 2, and so the
ideographs keep their 2 + 2. Widths written by hand from these documents.
"""

from __future__ import annotations

import pytest

from modalinfo.common.text import display_width

KNOWN = {
    "\U0001f44d\U0001f3fb": 2,  # thumbs up, light skin tone (first modifier)
    "\U0001f44d\U0001f3ff": 2,  # thumbs up, dark skin tone (last modifier)
    "\U0001f469\U0001f3ff\u200d\U0001f4bb": 2,  # woman technologist, dark skin tone
    "\u4e2d\u200d\u6587": 4,  # two CJK ideographs with a ZWJ between: letters
    "\uac00\u200d\uac01": 4,  # two Hangul syllables (W, category Lo) with a ZWJ
}


@pytest.mark.parametrize("text", list(KNOWN))
def test_display_width_by_hand(text):
    assert display_width(text) == KNOWN[text]
