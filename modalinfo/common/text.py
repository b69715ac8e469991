"""Terminal display width of text, for the plain-text tables the commands print.

Python's ``format(text, "<8")`` pads by code points, but a terminal shows a CJK
ideograph or an emoji in two columns and a combining mark (U+0303, a tilde above the
letter before it) in none, so a mode label holding either shifted every column after it.
The rule here is the one of Markus Kuhn's ``wcwidth`` (and of glibc's): a character of
Unicode East Asian Width ``W`` (wide) or ``F`` (fullwidth) takes two columns; a combining
mark (general category ``Mn`` or ``Me``), a format character (``Cf``: zero-width joiner;
the soft hyphen aside) or a Hangul medial / final jamo takes none; every other printable
character one. The standard library's ``unicodedata`` holds the properties: no
dependency is added. Emoji sequences joined by U+200D are counted character by character
(terminals disagree on them).
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
        character, 1 per other character (``len(text)`` for ASCII).
    """
    if text.isascii():
        return len(text)
    return sum(_char_width(c) for c in text)


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
