"""Terminal display width of text, for the plain-text tables the commands print.

Python's ``format(text, "<8")`` pads by code points, but a terminal shows a CJK
ideograph or an emoji in two columns and a combining mark (U+0303, a tilde above the
letter before it) in none, so a mode label holding either shifted every column after it.
The rule here is the one of Markus Kuhn's ``wcwidth`` (and of glibc's): a character of
Unicode East Asian Width ``W`` (wide) or ``F`` (fullwidth) takes two columns; a combining
mark (general category ``Mn`` or ``Me``), a format character (``Cf``: zero-width joiner;
the soft hyphen aside) or a Hangul medial / final jamo takes none; every other printable
character one. The standard library's ``unicodedata`` holds the properties: no
dependency is added.

Emoji are measured per grapheme cluster, as terminals show the common sequences of
Unicode UTS #51 (and as ``wcwidth.wcswidth`` >= 0.2.9 counts them): a zero-width joiner
(U+200D) joins the next character to the cluster before it, which keeps the width of
its first character (a family, man + ZWJ + woman + ZWJ + girl, is 2 columns, not 6);
variation selector 16 (U+FE0F, emoji presentation) makes a one-column base two wide
(U+2764 U+FE0F, a red heart, 2); a skin-tone modifier (U+1F3FB..U+1F3FF) makes its
base one 2-column emoji; a pair of regional indicators (a flag) is 2, one alone 1.
Letters never start an emoji: ``"a"`` + ZWJ + ``"b"`` stays 2 columns, as terminals
show it. Before,
each character counted alone (the family 6 columns, the heart 1: issue 27, left26-kde).
"""

from __future__ import annotations

import unicodedata

__all__ = ["display_width", "pad"]


def _char_width(char: str) -> int:
    """Columns a terminal gives one code point (0, 1 or 2)."""
    if char == "\u00ad":  # soft hyphen: Cf, but shown as a hyphen (as wcwidth)
        return 1
    if unicodedata.category(char) in ("Mn", "Me", "Cf") or "\u1160" <= char <= "\u11ff":
        return 0
    return 2 if unicodedata.east_asian_width(char) in ("W", "F") else 1


_ZWJ = "\u200d"
_VS16 = "\ufe0f"


def _is_skin_tone(char: str) -> bool:
    """Whether ``char`` is an emoji modifier (Fitzpatrick skin tone, U+1F3FB..U+1F3FF)."""
    return "\U0001f3fb" <= char <= "\U0001f3ff"


def _cluster_widths(text: str) -> int:
    """Columns of ``text``, summed over its emoji grapheme clusters (module notes)."""
    total = 0
    base = 0  # width of the current cluster so far (0: none to extend)
    emoji = False  # the current cluster starts with a symbol (a letter is never an emoji)
    joined = False  # the last character was a ZWJ after an emoji
    for char in text:
        if char == _ZWJ:
            joined = emoji and base == 2
            continue
        if joined:  # joined to the emoji: shown in its cell, which keeps its width
            joined = False
            continue
        if emoji and (char == _VS16 or _is_skin_tone(char)):
            # emoji presentation (VS16) or a skin tone: the cluster is one emoji, 2 wide
            total += 2 - base
            base = 2
            continue
        width = _char_width(char)
        if width:  # a new cluster; a zero-width mark stays in the one before
            total += width
            base = width
            emoji = not unicodedata.category(char).startswith("L")
    return total


def display_width(text: str) -> int:
    """Return the number of terminal columns ``text`` takes.

    Parameters
    ----------
    text : str
        One line of text (no control characters).

    Returns
    -------
    int
        Columns: 2 per wide or fullwidth character, 0 per combining mark or format
        character, 1 per other character (``len(text)`` for ASCII); an emoji
        sequence (ZWJ, VS16, skin tone) counts as its cluster (module notes).
    """
    if text.isascii():
        return len(text)
    return _cluster_widths(text)


def pad(text: str, width: int, align: str = "<") -> str:
    """Pad ``text`` with spaces to ``width`` terminal columns, as ``format`` pads ASCII.

    Parameters
    ----------
    text : str
        The cell's text; wider text is returned unchanged (never cut).
    width : int
        The column's width in terminal columns.
    align : {"<", ">"}
        Left (``"<"``) or right (``">"``) alignment.

    Returns
    -------
    str
        ``text`` with ``width - display_width(text)`` spaces after (``"<"``) or before
        (``">"``) it.
    """
    if align not in ("<", ">"):
        raise ValueError(f"`align` must be '<' or '>', got {align!r}")
    fill = " " * max(0, width - display_width(text))
    return text + fill if align == "<" else fill + text
