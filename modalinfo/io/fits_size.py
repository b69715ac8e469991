"""A FITS file's length against the sizes its headers declare: truncation in our words.

A FITS file is a sequence of HDUs, each a header of 2880-byte blocks of 80-character
cards ending with ``END``, then ``|BITPIX| / 8 x GCOUNT x (PCOUNT + NAXIS1 x ... x
NAXISn)`` bytes of data padded to a whole number of 2880-byte blocks (FITS Standard
4.0, sections 3.3 and 4.4.1.1; a compressed ``.fz`` tile table is a binary table whose
heap is PCOUNT). A file cut short was reported in astropy's or aotpy's words ("Header
missing END card", numpy's "buffer is too small", "Missing mandatory table
'AOT_DETECTORS'"), naming neither the truncation nor how much is missing (adversarial
round 53 PART b, Left). :func:`truncation` reads the headers only (the data are skipped
by seeking) and says which HDU the file ends in and the bytes found against the bytes
declared.
"""

from __future__ import annotations

import math
from pathlib import Path

from modalinfo.common.files import quoted
from modalinfo.io.files import LogFormatError

#: The FITS block, in bytes.
BLOCK = 2880

#: The header keywords the data size needs, and those naming an HDU or the extensions
#: that follow (NEXTEND, a common convention of multi-extension files)
_SIZE_KEYS = (b"BITPIX", b"NAXIS", b"PCOUNT", b"GCOUNT", b"GROUPS", b"XTENSION", b"EXTNAME",
              b"NEXTEND")


def _value(card: bytes) -> str:
    """Return the value field of a fixed-format card (bytes 11-80, before any ``/`` comment)."""
    text = card[10:].decode("ascii", "replace")
    if text.lstrip().startswith("'"):  # a string: XTENSION's
        return text.strip().split("'")[1].strip()
    return text.split("/")[0].strip()


def _data_bytes(cards: dict[bytes, str]) -> int | None:
    """Return the data bytes the header declares (unpadded); None if a size is unreadable."""
    try:
        bitpix = int(cards[b"BITPIX"])
        naxis = int(cards[b"NAXIS"])
        axes = [int(cards[f"NAXIS{k}".encode()]) for k in range(1, naxis + 1)]
        pcount = int(cards.get(b"PCOUNT", "0"))
        gcount = int(cards.get(b"GCOUNT", "1"))
    except (KeyError, ValueError):
        return None
    if naxis == 0:
        return 0
    if axes[0] == 0 and cards.get(b"GROUPS") == "T":  # random groups: NAXIS1 = 0
        axes = axes[1:]
    return abs(bitpix) // 8 * gcount * (pcount + math.prod(axes))


def _opens_hdu(block: bytes) -> bool:
    """Whether ``block`` starts an HDU: ``SIMPLE  =`` with the value T, or ``XTENSION=``."""
    if block.startswith(b"XTENSION="):
        return True
    return block.startswith(b"SIMPLE  =") and _value(block[:80]) == "T"


def _padded(n: int) -> int:
    return -(-n // BLOCK) * BLOCK


def truncation(path: Path, fmt: str = "FITS") -> str | None:
    """Return one line saying that the FITS file ``path`` ends before its headers' sizes; else None.

    See :func:`_walk`; a file whose HDUs are whole gives None.
    """
    said = _walk(path, fmt)
    return said if isinstance(said, str) else None


def whole_hdus(path: Path) -> list[dict[bytes, str]] | None:
    """Return the size cards of each HDU when ``path`` ends exactly after its last HDU.

    Returns
    -------
    list of dict or None
        One dict per HDU (its ``BITPIX``, ``NAXISn``, ``XTENSION``, ``EXTNAME``,
        ``NEXTEND`` ... cards as text, and ``b"_START"`` its first byte): the file holds
        whole HDUs and nothing after them, so a cut there is invisible to the sizes (it is
        a cut *between* two HDUs). None if the file is cut inside an HDU, has bytes after
        its last HDU, or a header cannot be read as FITS.
    """
    said = _walk(path, "FITS")
    return said if isinstance(said, list) else None


def _walk(path: Path, fmt: str) -> str | list[dict[bytes, str]] | None:
    """Walk the HDUs of ``path`` by their headers' sizes (the data are skipped by seeking).

    Parameters
    ----------
    path : pathlib.Path
        A file that starts as a FITS file (``SIMPLE  =``).
    fmt : str
        The format's name in the message ("FITS", "AOT").

    Returns
    -------
    str, list of dict or None
        ``"truncated FITS file 'x.fits': ..."`` naming the HDU the file ends in, the bytes
        its header declares (and with the padding to 2880-byte blocks) and the bytes found;
        the HDUs' size cards (:func:`whole_hdus`) if every HDU is whole; None if a header
        cannot be read as FITS (the parser then speaks: this check judges length only).
    """
    size = path.stat().st_size
    offset, index = 0, 0
    hdus: list[dict[bytes, str]] = []
    with open(path, "rb") as fh:
        while offset < size:
            start, cards, ended = offset, {}, False
            while not ended:
                fh.seek(offset)
                block = fh.read(BLOCK)
                if offset == start and not _opens_hdu(block):
                    return None  # not an HDU: trailing bytes, the parser's matter
                whole = len(block) - len(block) % 80
                if any(b < 0x20 or b > 0x7E for b in block[:whole]):
                    return None  # not FITS text: a damaged header, not a short file
                if len(block) < BLOCK:
                    return (f"truncated {fmt} file {quoted(path)}: it ends at byte {size}, "
                            f"inside the header of HDU {index} (from byte {start}; no END "
                            f"card in its {size - start} bytes, a header is whole 2880-byte "
                            "blocks ending with END); the file was cut short (an interrupted "
                            "copy or download?): copy it again")
                offset += BLOCK
                for i in range(0, BLOCK, 80):
                    card = block[i:i + 80]
                    key = card[:8].rstrip()
                    if key == b"END":
                        ended = True
                        break
                    if card[8:10] == b"= " and (key in _SIZE_KEYS or key.startswith(b"NAXIS")):
                        cards[key] = _value(card)
            need = _data_bytes(cards)
            if need is None:
                return None
            # the padding counts: a file cut inside it was "buffer is too small" (aotpy)
            # or "Empty or corrupt FITS file" (astropy; fix57-d), its data whole or not
            if offset + _padded(need) > size:
                kind = cards.get(b"XTENSION", "primary")
                where = ("; its data are whole, the padding after them is cut"
                         if offset + need <= size else "")
                return (f"truncated {fmt} file {quoted(path)}: HDU {index} ({kind}) declares "
                        f"{need} bytes of data ({_padded(need)} with the padding to "
                        f"2880-byte blocks) from byte {offset}, and the file has "
                        f"{size - offset} of them ({size} bytes in all, "
                        f"{offset + _padded(need)} expected at least){where}; the file was "
                        "cut short (an interrupted copy or download?): copy it again")
            offset += _padded(need)
            index += 1
            cards[b"_START"] = str(start)
            hdus.append(cards)
    return hdus if offset == size else None


def _hdu_name(cards: dict[bytes, str], index: int) -> str:
    """Name HDU ``index`` as a message does: ``HDU 2 (AOT_SOURCES)`` or ``HDU 0 (primary)``."""
    name = cards.get(b"EXTNAME") or cards.get(b"XTENSION") or "primary"
    return f"HDU {index} ({name})"


def cut_between(path: Path, fmt: str, missing: str) -> str | None:
    """Say that ``path`` may have been cut between two HDUs, when its reader misses one.

    Parameters
    ----------
    path : pathlib.Path
        A FITS (or AOT) file whose reader found an HDU missing.
    fmt : str
        The format's name in the message ("FITS", "AOT").
    missing : str
        What the reader misses, e.g. ``"no table 'AOT_DETECTORS', which every AOT file
        has"``.

    Returns
    -------
    str or None
        ``"incomplete AOT file 'x.fits': <missing>; the file ends at byte N, right after
        HDU k (NAME), where nothing tells that it ends: ..."``; None if the file does not
        end exactly after a whole HDU (the reader's own words are then the right ones).
    """
    hdus = whole_hdus(path)
    if not hdus:
        return None
    last = len(hdus) - 1
    return (f"incomplete {fmt} file {quoted(path)}: {missing}; the file ends at byte "
            f"{path.stat().st_size}, right after {_hdu_name(hdus[last], last)}, exactly "
            "between two HDUs: it was cut there (an interrupted copy or download: copy it "
            "again) or written without that HDU")


def _missing_extensions(path: Path, fmt: str) -> str | None:
    """Say that ``path`` holds fewer extensions than its primary header's NEXTEND."""
    hdus = whole_hdus(path)
    if not hdus:
        return None
    try:
        declared = int(hdus[0].get(b"NEXTEND", ""))
    except ValueError:
        return None  # no NEXTEND (or an unreadable one): nothing declares the count
    present = len(hdus) - 1
    if present >= declared:
        return None
    last = len(hdus) - 1
    return (f"incomplete {fmt} file {quoted(path)}: its primary header declares NEXTEND = "
            f"{declared} extensions and the file holds {present}, ending at byte "
            f"{path.stat().st_size} right after {_hdu_name(hdus[last], last)}, exactly "
            "between two HDUs: the file was cut short (an interrupted copy or download?): "
            "copy it again")


def check_whole(path: Path, fmt: str = "FITS") -> None:
    """Raise ``LogFormatError`` if ``path`` is cut short.

    Inside an HDU (:func:`truncation`'s line), or between two HDUs when the primary
    header's NEXTEND declares more extensions than the file holds (a FITS with EXTEND = T
    and NEXTEND = 3 and two extensions read its first one as the log; fix56-c).
    """
    said = truncation(path, fmt) or _missing_extensions(path, fmt)
    if said is not None:
        raise LogFormatError(said)
