"""Figure files with leading bytes, and FITS header bytes (review37, issue 27).

References (outside the code under test): the SVG 1.1 and HTML documents as editors
save them, a UTF-8 byte-order mark (``EF BB BF``) and a line break before the first tag
or an XML declaration (XML 1.0 allows them before the root element); the FITS 4.0
standard, section 4.1.2.1:
a header holds only the printable ASCII text 0x20-0x7E, so a file whose header holds a
0x7F (DEL) byte is not a FITS header and is left to the parser ("corrupt"), not called
truncated. Files written here byte by byte.
"""

from __future__ import annotations

import re

import pytest

from modalinfo.io.files import LogFormatError
from modalinfo.io.fits_size import truncation
from modalinfo.io.formats import detect_format


@pytest.mark.parametrize("lead", [b"\xef\xbb\xbf", b"\n  ", b"\xef\xbb\xbf\r\n",
                                  b'<?xml version="1.0" encoding="UTF-8"?>\n'])
def test_an_svg_after_a_bom_or_line_break_is_named(tmp_path, lead):
    path = tmp_path / "fig.svg"
    path.write_bytes(lead + b'<svg xmlns="http://www.w3.org/2000/svg" width="10" '
                     b'height="10"><rect width="10" height="10"/></svg>\n')
    with pytest.raises(LogFormatError, match=re.escape("is an SVG image, not a log")):
        detect_format(path)


def _card(text: str) -> bytes:
    return text.ljust(80).encode("ascii")


def test_a_del_byte_in_the_header_is_not_read_as_a_short_file(tmp_path):
    cards = [_card("SIMPLE  =                    T"), _card("BITPIX  =                  -64"),
             _card("NAXIS   =                    2"), _card("NAXIS1  =                   10"),
             _card("NAXIS2  =                  100"),
             _card("COMMENT x").replace(b"x", b"\x7f"), _card("END")]
    header = b"".join(cards).ljust(2880, b" ")
    good = tmp_path / "good.fits"
    good.write_bytes(header.replace(b"\x7f", b"x") + bytes(2880))   # 8000 bytes due
    assert "truncated" in (truncation(good) or "")                   # the rule applies
    bad = tmp_path / "bad.fits"
    bad.write_bytes(header + bytes(2880))
    assert truncation(bad) is None


def test_simple_false_is_not_read_as_a_short_fits_file(tmp_path):
    # FITS 4.0 section 4.4.1.1: SIMPLE = F does not conform; its sizes are not FITS's
    cards = [_card("SIMPLE  =                    F"), _card("BITPIX  =                  -64"),
             _card("NAXIS   =                    1"), _card("NAXIS1  =                 1000"),
             _card("END")]
    path = tmp_path / "nonconforming.fits"
    path.write_bytes(b"".join(cards).ljust(2880, b" ") + bytes(2880))
    assert truncation(path) is None
