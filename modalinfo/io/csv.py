"""CSV logs: human-readable and lossless.

Layout written by :func:`write_csv`::

    # modalinfo: {"modalinfo":1,"shape":[T,M],"dtype":"float64","rate":1000.0,...}
    time,Z2,Z3,Z4            <- header row (``time`` only with explicit timestamps)
    0.0,1.25e-07,...         <- one row per frame
    # end of modalinfo log   <- end marker: a truncated file is always detected

Values are written with Python's ``repr`` of the float64 value, the shortest
decimal that reads back to the same double, so float64 round-trips bitwise; a
float32 log is written from its exact float64 values and cast back (also bitwise),
with the dtype recorded in the header. The JSON header also carries a SHA-256 of
the coefficients (and timestamps), verified on reading: an edited or damaged file
raises :class:`~modalinfo.io.LogFormatError` (pass ``verify=False`` to accept a
deliberately edited file).

Foreign CSV (no ``# modalinfo:`` line): optional ``# key: value`` comment lines
(kept as string metadata), an optional header row, then numbers separated by
commas, semicolons, tabs or blanks. A column (in any position) named ``time``,
``t``, ``time_s``, ``timestamp`` (seconds), ``time_ms`` (milliseconds, converted) or
``frame`` (frame numbers: times only with a ``rate`` hint) gives the time axis.
Header names ``Z2``, ``z_2``, ``noll2``, ``mode_2``, ``a2``, ``A<j>`` (ANSI), ... give
the modes (see ``modalinfo.io._columns``); other names become labels, and
``modes=``/``convention=`` hints may relabel them. Missing information comes from
hints; a likely transposed table (far more columns than rows, no header) is
refused unless ``transpose=`` says which way round it is.
"""

from __future__ import annotations

import csv as _csv
import io
import re
from pathlib import Path
from typing import Any

import numpy as np

from modalinfo.common.files import (
    as_path,
    atomic_write,
    check_readable,
    quoted,
    warn_spreadsheet_formulas,
)
from modalinfo.io._columns import (
    column_units,
    mode_columns,
    set_timestamps,
    time_kind,
    unit_text,
)
from modalinfo.io._common import (
    build_log,
    dumps,
    log_header,
    parse_header,
    reading,
    stored_from_header,
    unwrap,
    verify_checksum,
)
from modalinfo.io.files import LogFormatError
from modalinfo.telemetry.checks import mode_labels
from modalinfo.telemetry.log import ModalLog

__all__ = ["read_csv", "write_csv"]

_MAGIC = "# modalinfo:"
_END = "# end of modalinfo log"
_ROWS_PER_WRITE = 4096



def _cell(text: str) -> float:
    """Return one CSV cell as a float; an empty (or blank) cell is a missing value, NaN."""
    text = text.strip()
    return float(text) if text else float("nan")

def write_csv(log: ModalLog, path, *, overwrite: bool = False) -> Path:
    """Write ``log`` to a CSV file (exact decimal values), atomically.

    Parameters
    ----------
    log : ModalLog
        The log.
    path : str or os.PathLike
        Target file.
    overwrite : bool
        Replace an existing file; otherwise ``FileExistsError``.

    Returns
    -------
    pathlib.Path
        The written path.
    """
    if not isinstance(log, ModalLog):
        raise TypeError(f"`log` must be a ModalLog; got {type(log).__name__}.")
    path = as_path(path)
    header = log_header(log, checksum=True)
    times = log.timestamps
    warn_spreadsheet_formulas(log.labels, f"CSV {quoted(path.name)}")

    def write(fh):
        text = io.TextIOWrapper(fh, encoding="utf-8", newline="\n")
        text.write(f"{_MAGIC} {dumps(header)}\n")
        names = (["time"] if times is not None else []) + log.labels
        _csv.writer(text, lineterminator="\n").writerow(names)
        for i0, block in zip(
            range(0, log.n_frames, _ROWS_PER_WRITE), log.iter_chunks(_ROWS_PER_WRITE), strict=True
        ):
            rows = block.astype(np.float64).tolist()
            if times is not None:
                tt = times[i0 : i0 + block.shape[0]].tolist()
                lines = [",".join(map(repr, [t, *row])) for t, row in zip(tt, rows, strict=True)]
            else:
                lines = [",".join(map(repr, row)) for row in rows]
            text.write("\n".join(lines))
            text.write("\n")
        text.write(f"{_END}\n")
        text.flush()
        text.detach()

    return atomic_write(path, write, overwrite=overwrite)


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


#: a date and time written as text (ISO 8601 and its spreadsheet variants)
_DATETIME_TEXT = re.compile(r"\d{4}-\d{2}-\d{2}[T ]\d{2}:\d{2}")
_INTEGER = re.compile(r"\+?\d+")
_FLOAT = re.compile(r"[+-]?(?:\d+\.\d*|\.\d+|\d+(?:\.\d*)?[eE][+-]?\d+)(?:[eE][+-]?\d+)?")


#: a number written with a decimal comma ('0,25', '-1,5E-03') or thousands separators
_DECIMAL_COMMA = re.compile(r"[+-]?\d+,\d+(?:[eE][+-]?\d+)?")
_THOUSANDS = re.compile(r"[+-]?\d{1,3}(?:[,.\u00a0' ]\d{3})+(?:[.,]\d*)?")


def _number_format(message: str, path, delim: str | None = ",") -> None:
    """Refuse numbers in a spreadsheet's locale format, which numpy called "corrupt".

    A German / French spreadsheet's CSV ('0,25' with ';' between values) and numbers
    with thousands separators ('1,000.5') were "corrupt CSV file ... could not convert
    string" (round 14 PART b, F18, F27, F30). The advice names the file's own
    delimiter ``delim``: pandas' default ',' read a ';' file as one column, and ';' a
    ',' file (review13).
    """
    found = re.search(r"could not convert string '([^']*)'", message)
    if not found:
        return
    token = found.group(1).strip().strip('"')
    given = r"r'\s+'" if delim is None else repr(delim)  # pandas' sep for this file
    if _THOUSANDS.fullmatch(token) and not _DECIMAL_COMMA.fullmatch(token):
        what = "thousands separators"
        sep = re.search(r"\d([^\d])\d{3}", token).group(1)
        read = (f"sep={given}, " if delim != "," else "") + f"thousands={sep!r}" + (
            ", decimal=','" if sep == "." else "")
    elif _DECIMAL_COMMA.fullmatch(token):
        what = "a decimal comma (a spreadsheet in a German / French locale)"
        read = f"sep={given}, decimal=','"
    else:
        return
    raise LogFormatError(
        f"CSV file {quoted(path)}: numbers such as {token!r} are written with {what}; modalinfo "
        "reads numbers with a decimal point and no separators: re-save the file so (pandas: "
        f"pd.read_csv(path, {read}).to_csv(new, index=False))")


_NUMPY_REPR = re.compile(r"np\.(?:float|int|uint|complex)\d*\(([^()']*)\)")


def _numpy_reprs(message: str, path) -> None:
    """Refuse cells written as numpy scalar reprs (``np.float64(0.5)``), naming them so.

    numpy >= 2 prints a scalar's ``repr`` that way: a CSV written with ``f"{x!r}"`` or
    ``repr(x)`` of numpy values was "corrupt CSV file ...: could not convert string
    'np.float64(0.5)'", read on the command line as '0.5' (round 35 PART b, E01).
    """
    found = re.search(r"could not convert string '([^']*)'", message)
    if not found or not _NUMPY_REPR.fullmatch(found.group(1).strip().strip('"')):
        return
    cell = found.group(1).strip().strip('"')
    raise LogFormatError(
        f"CSV file {quoted(path)}: cells such as {cell!r} are numpy scalar reprs (numpy >= 2 "
        "prints repr(x) so), not numbers; write the numbers themselves (str(float(x)), "
        "numpy.savetxt, or pandas' to_csv)")


def _prose_lines(body: list[str], delim: str | None, path, first: str | None = None) -> None:
    """Refuse lines of text above the numbers (a header block not marked with ``#``).

    A file opening with 'KAOS telemetry dump' / 'rate: 1000 Hz' / 'units: nm' above
    its numbers was "corrupt CSV file ...: could not convert string 'rate:' to float64
    at row 0, column 1" (round 31 PART b, a30): row 0 was the file's second line and no
    word said how to mark such lines. Raised when the rows before the first row of
    numbers (among the first 50) are text: fewer numbers than half of their cells, or
    not as many fields (a frame with a bad cell or two keeps numpy's message naming it;
    until review23 one number made a frame, so 'rate: 1000 Hz' above a 3-column log was
    "corrupt" again). ``delim`` was guessed from the first line, which is prose here:
    'KAOS telemetry dump' has no comma above comma-separated numbers, so the numbers are
    also split by the delimiter of the last line looked at (round 32 PART b, b22).
    ``first`` is the line read as the column names: one such line without the numbers'
    delimiter above them (a title, b58) is named too.
    """
    lead = 0
    last = _delimiter(body[min(len(body), 50) - 1])
    for sep in dict.fromkeys((delim, last)):
        rows = [_split(line, sep) for line in body[:50]]
        # the first row of numbers (an empty cell is a missing value, not text)
        lead = next((k for k, row in enumerate(rows)
                     if all(_is_number(tok) for tok in row if tok.strip())), 0)
        if lead:
            break
    if lead == 0:
        if (first is not None and last != delim and len(rows[0]) > 1
                and len(_split(first, last)) == 1 and all(_is_number(t) for t in rows[0])):
            raise LogFormatError(
                f"CSV file {quoted(path)}: its first line {first.strip()[:40]!r} is text above "
                f"numbers separated by {'blanks' if last is None else repr(last)}; start "
                "it with '#' (comment lines are skipped) or, if it names the columns, "
                "separate the names as the numbers are")
        return
    width = len(rows[lead])
    if any(len(row) == width
           and 2 * sum(_is_number(tok) or not tok.strip() for tok in row) >= width
           for row in rows[:lead]):
        return  # a frame with a bad cell ('N/A'), not a line of text: numpy names the cell
    raise LogFormatError(
        f"CSV file {quoted(path)}: its first {lead + 1} lines are text above the numbers "
        f"(such as {body[0].strip()[:40]!r}); start each such line with '#' (comment lines "
        "are skipped, '# units: nm' is read) and keep at most one row of column names")


def _ragged_row(message: str, body: list[str], delim: str | None, path) -> None:
    """Refuse a row of another length naming it, a cut last row as such.

    numpy's message ("the number of columns changed from 28 to 19 at row 8000; use
    `usecols` to select a subset and avoid this error") gave advice for its own API and
    no cause: a logger that stopped while writing leaves a last line with fewer values
    (adversarial round 34 PART b, B44-B47). ``body`` are the data lines.
    """
    if "number of columns changed" not in message:
        return
    rows = [k for k, line in enumerate(body) if line.strip()]
    if not rows:
        return
    width = len(_split(body[rows[0]], delim))
    bad = next((k for k in rows if len(_split(body[k], delim)) != width), None)
    if bad is None:
        return
    got = len(_split(body[bad], delim))
    number = rows.index(bad) + 1
    if bad == rows[-1] and got < width:
        raise LogFormatError(
            f"corrupt CSV file {quoted(path)}: its last data row ({number}) holds {got} of the "
            f"{width} "
            "values of the rows above: the file ends mid-row (written while the logger "
            "stopped?); delete that partial last line to read the complete frames")
    raise LogFormatError(
        f"corrupt CSV file {quoted(path)}: data row {number} holds {got} values where the rows "
        "above "
        f"hold {width}; every row must hold one value per column")


def _text_key(message: str, names: list[str], path) -> None:
    """Refuse a text key column (``night``: '2024-01-01') beside named mode columns.

    numpy's message named the cell, not the cause ("corrupt CSV file ...: could not
    convert string '2024-01-01' to float64 at row 0, column 1"), while the same key
    written as numbers gets the key-column refusal of ``mode_columns`` with its
    advice (adversarial round 30 PART b, K04). A time column keeps its own messages.
    """
    found = re.search(r"could not convert string '([^']+)'.* column (\d+)", message)
    if not found:
        return
    k = int(found.group(2)) - 1  # numpy counts columns from 1
    if 0 <= k < len(names) and time_kind(names[k]) is None:
        mode_columns([n for n in names if time_kind(n) is None], path)


def _index_row(first: list[str], second: list[str] | None) -> bool:
    """Whether an all-numeric first row is a header of mode indices (``2,3,4,...``).

    It is when it has at least two entries, all integer literals counting up by one from
    0, 1 or 2 (the first index of the ANSI, Noll-with-piston and Noll-after-piston
    lists), and the next row holds a finite number written with a decimal point or an
    exponent. Measured coefficients are not exact consecutive integers, so such a row
    read as data was a silent extra frame (audit 9, f04); rows of integer data (every
    entry an integer literal) stay data.
    """
    if second is None or len(second) != len(first) or len(first) < 2:
        return False
    if not all(_INTEGER.fullmatch(tok) for tok in first):
        return False
    values = [int(tok) for tok in first]
    if values[0] not in (0, 1, 2) or values != list(range(values[0], values[0] + len(values))):
        return False
    return any(_FLOAT.fullmatch(tok) for tok in second)


def _delimiter(line: str) -> str | None:
    for delim in (",", ";", "\t"):
        if delim in line:
            return delim
    return None  # any run of blanks


def _split(line: str, delim: str | None) -> list[str]:
    if delim is None:
        return line.split()
    return [tok.strip() for tok in next(_csv.reader([line], delimiter=delim))]


def _integer_column(body: list[str], delim: str | None, k: int, column: np.ndarray):
    """Column ``k`` of ``body`` as int64 where every value is an integer, else ``column``.

    int64 ns since 1970 lose digits in float64 (:func:`set_timestamps`).
    """
    if not np.all(np.floor(column) == column):
        return column
    try:
        return np.loadtxt(body, delimiter=delim, dtype=np.int64, ndmin=1, comments=None,
                          quotechar='"', usecols=k)
    except (ValueError, OverflowError):  # "1.5e3", or beyond int64: the floats as read
        return column


def _time_columns(
    values: np.ndarray, names: list[str], path: Path, stored: dict, meta: dict,
    body: list[str] | None = None, delim: str | None = None,
) -> tuple[np.ndarray, list[str]]:
    """Take the time column (any position) out of ``values``; return the mode columns.

    Seconds and milliseconds become ``stored["timestamps"]`` (s); frame numbers
    ``stored["_frame_numbers"]`` (times only with a rate). A frame-number column
    beside a time column is dropped (recorded in ``meta``); two time columns are
    refused.
    """
    kinds = [time_kind(n) for n in names]
    timed = [k for k, kind in enumerate(kinds) if kind not in (None, "frame")]
    framed = [k for k, kind in enumerate(kinds) if kind == "frame"]
    if len(timed) > 1 or len(framed) > 1:
        both = [names[k] for k in (timed if len(timed) > 1 else framed)]
        raise LogFormatError(
            f"CSV file {quoted(path)} has {len(both)} time columns ({', '.join(both)}); expected "
            "one"
        )
    drop = timed + framed
    if timed:
        k = timed[0]
        column = np.ascontiguousarray(values[:, k])
        if body is not None:
            column = _integer_column(body, delim, k, column)
        set_timestamps(column, kinds[k], stored, meta)
        if kinds[k] != "s":
            meta["time_column"] = f"{names[k]} ({kinds[k]}, converted to s)"
        if framed:
            meta["frame_column"] = f"{names[framed[0]]} (frame numbers, unused: the file has times)"
    elif framed:
        stored["_frame_numbers"] = np.ascontiguousarray(values[:, framed[0]])
    keep = [k for k in range(len(names)) if k not in drop]
    if not keep:
        raise LogFormatError(f"CSV file {quoted(path)} has a time column but no modes (no mode "
                             "column)")
    return values[:, keep], [names[k] for k in keep]


@unwrap
def read_csv(path, *, verify: bool = True, **hints) -> ModalLog:
    """Read a log from a CSV file written by :func:`write_csv` or by other software.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    verify : bool
        Check the SHA-256 recorded by :func:`write_csv` (modalinfo files only).
    **hints
        ``rate``, ``timestamps``, ``modes``, ``convention``, ``units``, ``wavelength``,
        ``metadata``, ``nonfinite``, ``start_time``: fill what the file lacks; a hint
        contradicting the file raises ``ValueError``.

    Returns
    -------
    ModalLog
        The log.

    Raises
    ------
    LogFormatError
        Undecodable text, ragged or non-numeric rows, a header disagreeing with the
        data, or a checksum mismatch.
    """
    path = as_path(path)
    check_readable(path)
    with reading("CSV", path):
        # utf-8-sig: a byte-order mark (spreadsheet exports) is not part of the first name
        with open(path, encoding="utf-8-sig", newline="") as fh:
            lines = fh.read().splitlines()
        header = None
        comments: dict[str, str] = {}
        k = 0
        while k < len(lines) and (lines[k].startswith("#") or not lines[k].strip()):
            line = lines[k]
            if line.startswith(_MAGIC) and not line[len(_MAGIC):].lstrip().startswith("{"):
                # paper_figures' report.md ("# modalinfo: regenerated figures ...") was a
                # "corrupt CSV file: unreadable header (Expecting value ...)" (round 43
                # PART b, g10)
                raise LogFormatError(
                    f"{quoted(path)} is not a modalinfo CSV: its '{_MAGIC}' line is not a "
                    "modalinfo "
                    "CSV header (a text file, such as the report of `python -m paper_figures`?)"
                    "; a log is an NPZ, NPY, CSV, FITS or HDF5 file of coefficients")
            if line.startswith(_MAGIC):
                header = parse_header(line[len(_MAGIC) :], "CSV", path, verify=verify)
                k += 1
                break  # the header row follows immediately
            elif '{"modalinfo":' in line:
                raise LogFormatError(f"corrupt CSV file {quoted(path)}: damaged '# modalinfo:' "
                                     "line")
            elif ":" in line:
                key, _, value = line[1:].partition(":")
                if key.strip():
                    comments[key.strip()] = value.strip()
            k += 1
        names = None
        first_line: str | None = None
        if header is not None:  # modalinfo layout: header row, then exactly T data rows
            if k >= len(lines):
                raise LogFormatError(f"corrupt CSV file {quoted(path)}: header row missing")
            delim = ","
            names = _split(lines[k], delim)
            body = lines[k + 1 :]
            while body and not body[-1].strip():
                body.pop()  # blank lines an editor or a transfer appended are not data
            if _END in body[:-1]:
                # also when the appended lines end in a marker of their own (another log's
                # tail): "data row 2001 holds 1 values" named the marker (round 40 PART b, F53)
                raise LogFormatError(
                    f"corrupt CSV file {quoted(path)}: {len(body) - 1 - body.index(_END)} "
                    f"line(s) after the end marker {_END!r} (appended to the log?)"
                )
            if not body or body[-1] != _END:
                raise LogFormatError(
                    f"corrupt CSV file {quoted(path)}: end marker {_END!r} missing (truncated?)"
                )
            body = body[:-1]
            if not body:
                raise LogFormatError(f"corrupt CSV file {quoted(path)}: no data rows (truncated?)")
        else:
            body = [ln for ln in lines[k:] if ln.strip() and not ln.startswith("#")]
            if not body:
                raise LogFormatError(f"CSV file {quoted(path)} has no data rows")
            delim = _delimiter(body[0])
            first_line = body[0]
            first = _split(first_line, delim)
            if not all(_is_number(tok) for tok in first) or _index_row(
                first, _split(body[1], delim) if len(body) > 1 else None
            ):
                names = first
                body = body[1:]
                if all(_is_number(tok) for tok in first):
                    comments["header_row"] = (
                        f"first row {', '.join(first[:3])}, ... read as mode indices, not data"
                    )
                if not body:
                    raise LogFormatError(f"CSV file {quoted(path)} has a header row but no data "
                                         "rows")
        try:
            values = np.loadtxt(body, delimiter=delim, dtype=np.float64, ndmin=2,
                                comments=None, quotechar='"')  # QUOTE_ALL quotes numbers too
        except ValueError as exc:
            when = _DATETIME_TEXT.search(str(exc))
            if when:  # ISO dates are not a damaged file (round 13 PART b, T03 / T08)
                raise LogFormatError(
                    f"CSV file {quoted(path)}: a column holds dates and times as text "
                    f"({when.group(0)!r}...); times are read as numbers of seconds: "
                    "convert that column to seconds (pandas: (t - t[0]).dt.total_seconds()) "
                    "or delete it and give --rate HZ") from None
            _number_format(str(exc), path, delim)
            _ragged_row(str(exc), body, delim, path)
            if names is not None:
                _text_key(str(exc), names, path)
            _numpy_reprs(str(exc), path)  # after a key column's refusal, which comes first
            if "string ''" not in str(exc):
                if names is not None:
                    _prose_lines(body, delim, path, first_line)
                raise
            # an empty cell is how pandas / spreadsheets write a missing value: it is a
            # NaN for --nonfinite to handle, not a "corrupt CSV file" (round 12 PART b, A07)
            values = np.loadtxt(body, delimiter=delim, dtype=np.float64, ndmin=2,
                                comments=None, quotechar='"', converters=_cell)
        if header is None and names is not None:
            # a spreadsheet's trailing empty columns (no name, no value: 'Z6,,' rows)
            # were "modes must be non-empty str labels; got ''" (round 14 PART b, F19, F20)
            while (len(names) > 1 and not names[-1] and len(names) == values.shape[1]
                   and np.isnan(values[:, -1]).all()):
                names, values = names[:-1], values[:, :-1]
        if names is not None and len(names) != values.shape[1]:
            raise LogFormatError(
                f"CSV file {quoted(path)}: header row has {len(names)} names but rows have "
                f"{values.shape[1]} values"
            )
        if header is not None:
            stored = stored_from_header(header)
            n_time = 1 if header["has_timestamps"] else 0
            if values.shape[1] != header["shape"][1] + n_time:
                raise LogFormatError(
                    f"corrupt CSV file {quoted(path)}: rows have {values.shape[1]} values, header "
                    f"announces {header['shape'][1]} modes"
                    + (" plus a time column" if n_time else "")
                )
            if values.shape[0] != header["shape"][0]:
                raise LogFormatError(
                    f"corrupt CSV file {quoted(path)}: {values.shape[0]} rows, header announces "
                    f"{header['shape'][0]} (truncated?)"
                )
            expected_names = (["time"] if n_time else []) + [
                name.strip() for name in mode_labels(header["modes"], header["convention"])
            ]
            if verify and names != expected_names:
                raise LogFormatError(
                    f"corrupt CSV file {quoted(path)}: header row {names!r} does not match the "
                    "modes "
                    "recorded in the '# modalinfo:' line"
                )
            coeffs = np.ascontiguousarray(values[:, n_time:], dtype=header["dtype"])
            if n_time:
                stored["timestamps"] = np.ascontiguousarray(values[:, 0])
            if verify:
                verify_checksum(header, "coefficients", coeffs, "CSV", path)
                if n_time:
                    verify_checksum(header, "timestamps", stored["timestamps"], "CSV", path)
        else:
            stored: dict[str, Any] = {}
            coeffs = values
            meta = {**comments, "source_file": path.name, "source_format": "csv"}
            unit = None
            for key, value in comments.items():  # '# units: nm', '# Unit : nm', ...
                if key.lower() in ("units", "unit") and unit_text(value) is not None:
                    unit = (unit_text(value), f"comment line '# {key}:'")
                    break
            if names is not None:
                coeffs, names = _time_columns(values, names, path, stored, meta, body,
                                              delim)
                names, suffix = column_units(names, path)
                if suffix is not None:
                    if unit is not None and unit[0].lower() != suffix.lower():
                        raise LogFormatError(
                            f"CSV file {quoted(path)}: its {unit[1]} says {unit[0]!r} but its mode "
                            f"columns say {suffix!r}; one log holds one unit"
                        )
                    unit = (suffix, "mode column names")
                stored["modes"], stored["convention"], assumed = mode_columns(names, path)
                if assumed:
                    stored["_convention_assumed"] = True
            stored["metadata"] = meta
            if unit is not None:
                stored["_unit"] = unit
            coeffs = np.ascontiguousarray(coeffs)
    return build_log(coeffs, path, stored, hints, foreign=header is None)
