"""NumPy ``.npz`` logs (lossless) and plain ``.npy`` arrays (foreign, with hints).

Layout written by :func:`write_npz` (``numpy.savez``, uncompressed):

``coefficients``
    ``(T, M)`` float32 or float64, as in the log;
``timestamps``
    ``(T,)`` float64 seconds, only when the log has explicit timestamps;
``header``
    0-d unicode array holding the JSON header (modes, units, rate, metadata, ...).

Reading parses the zip members with :mod:`zipfile` and the ``.npy`` headers with
:mod:`numpy.lib.format` (never unpickling: object arrays are refused, like
``allow_pickle=False``), checks every member's declared size against its stored size
and its CRC-32 (read in full), so truncated or altered files raise
:class:`~modalinfo.io.LogFormatError` naming the file. ``mmap=True`` memory-maps
the coefficients of an uncompressed member in place (size-checked; the CRC is then
not verified, since that would read the whole member).
"""

from __future__ import annotations

import struct
import zipfile
from pathlib import Path
from typing import Any

import numpy as np

from modalinfo.common.files import as_path, atomic_write, check_readable, quoted
from modalinfo.io._columns import (
    float_columns,
    mode_arrays,
    mode_columns,
    time_arrays,
    unit_text,
)
from modalinfo.io._common import (
    build_log,
    check_stored_coefficients,
    dumps,
    log_header,
    parse_header,
    reading,
    stored_from_header,
    unwrap,
)
from modalinfo.io._foreign import rate_field
from modalinfo.io.files import LogFormatError as _LogFormatError
from modalinfo.telemetry.log import ModalLog

__all__ = ["read_npz", "write_npz", "read_npy"]

_COEFF_NAMES = ("coefficients", "coeffs", "coefs", "data", "zernike")


def write_npz(log: ModalLog, path, *, overwrite: bool = False) -> Path:
    """Write ``log`` to an uncompressed ``.npz`` file, atomically.

    Parameters
    ----------
    log : ModalLog
        The log.
    path : str or os.PathLike
        Target file (the name is used as given; no extension is appended).
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
    arrays: dict[str, Any] = {
        "coefficients": np.ascontiguousarray(log.coeffs),
        "header": np.array(dumps(log_header(log, checksum=False))),
    }
    if log.timestamps is not None:
        arrays["timestamps"] = log.timestamps
    return atomic_write(path, lambda fh: np.savez(fh, **arrays), overwrite=overwrite)


def _npy_header(fh) -> tuple[tuple[int, ...], bool, np.dtype]:
    version = np.lib.format.read_magic(fh)
    if version == (1, 0):
        return np.lib.format.read_array_header_1_0(fh)
    if version in ((2, 0), (3, 0)):
        return np.lib.format.read_array_header_2_0(fh)
    raise ValueError(f"unsupported .npy format version {version}")


def _nbytes(shape, dtype) -> int:
    return int(np.prod(shape, dtype=np.int64)) * dtype.itemsize


def _check_dtype(dtype: np.dtype, what: str) -> None:
    if dtype.hasobject:
        raise ValueError(f"{what} holds Python objects (pickles are never loaded)")


def _read_member(zf: zipfile.ZipFile, name: str) -> np.ndarray:
    info = zf.getinfo(name)
    with zf.open(info) as fh:
        shape, fortran, dtype = _npy_header(fh)
        _check_dtype(dtype, f"member {name!r}")
        header_len = fh.tell()
        need = _nbytes(shape, dtype)
        if info.file_size != header_len + need:
            raise ValueError(
                f"member {name!r} declares {need} data bytes but stores "
                f"{info.file_size - header_len}"
            )
        raw = fh.read()  # reading to the end verifies the CRC-32
    if len(raw) != need:
        raise ValueError(f"member {name!r} is truncated")
    return np.frombuffer(raw, dtype=dtype).reshape(shape, order="F" if fortran else "C")


def _mmap_member(path: Path, zf: zipfile.ZipFile, name: str) -> np.ndarray | None:
    """Memory-map an uncompressed member in place, or None if it is compressed."""
    info = zf.getinfo(name)
    if info.compress_type != zipfile.ZIP_STORED:
        return None
    with open(path, "rb") as raw:
        raw.seek(info.header_offset)
        local = raw.read(30)
        if len(local) != 30 or local[:4] != b"PK\x03\x04":
            raise ValueError(f"bad local header for member {name!r}")
        name_len, extra_len = struct.unpack("<HH", local[26:30])
        start = info.header_offset + 30 + name_len + extra_len
        raw.seek(start)
        shape, fortran, dtype = _npy_header(raw)
        _check_dtype(dtype, f"member {name!r}")
        offset = raw.tell()
    need = _nbytes(shape, dtype)
    if info.file_size != offset - start + need:
        raise ValueError(f"member {name!r} declares {need} data bytes but stores less")
    if path.stat().st_size < offset + need:
        raise ValueError(f"member {name!r} is truncated")
    if need == 0:
        return np.empty(shape, dtype=dtype)
    return np.memmap(
        path, dtype=dtype, mode="r", offset=offset, shape=shape, order="F" if fortran else "C"
    )


def _check_entry_count(path: Path, zf: zipfile.ZipFile) -> None:
    """Compare the entries zipfile parsed with the count in the end-of-directory record.

    A damaged central directory can make :mod:`zipfile` skip members silently; the
    end record (the last 22 bytes when the archive has no comment, as ``numpy.savez``
    writes it) states how many there are. Zip64 archives (count 0xFFFF) are skipped.
    """
    with open(path, "rb") as fh:
        fh.seek(0, 2)
        size = fh.tell()
        if size < 22:
            return
        fh.seek(size - 22)
        end = fh.read(22)
    if end[:4] != b"PK\x05\x06":
        return
    total = struct.unpack("<H", end[10:12])[0]
    if total != 0xFFFF and total != len(zf.infolist()):
        raise ValueError(
            f"the zip directory lists {len(zf.infolist())} members but its end record {total}"
        )


def _refuse_orphan_header(zf, names: dict, path: Path) -> None:
    """Refuse a modalinfo header without its ``coefficients`` member (renamed?).

    The file was read as a foreign one: its header (rate, units, modes, wavelength)
    ignored, and "does not record its units" said (adversarial round 25 PART b, N10).
    A ``header`` member that is not modalinfo's JSON is another tool's: no refusal.
    """
    import json

    try:
        text = _read_member(zf, names["header"])
        parsed = json.loads(str(text[()])) if text.dtype.kind == "U" and not text.shape else None
    except (ValueError, TypeError, OSError):
        return
    if isinstance(parsed, dict) and "modalinfo" in parsed:
        raise _LogFormatError(
            f"NPZ file {quoted(path)} holds a modalinfo header but no 'coefficients' member "
            f"(members: {', '.join(sorted(names))}): renamed? Rename it back to keep the "
            "header's rate, units and modes, or name the array with dataset= (command "
            "line: --dataset NAME) to read it without them")


@unwrap
def read_npz(path, *, mmap: bool = False, dataset: str | None = None, **hints) -> ModalLog:
    """Read a log from a ``.npz`` file written by :func:`write_npz` or by other software.

    A foreign ``.npz`` (no modalinfo header) must hold exactly one 2-D numeric array
    (or one named ``coefficients``/``coeffs``/``data``, or the one named by
    ``dataset``) or one 1-D array per mode named ``z2``, ``noll_3``, ... (see
    ``modalinfo.io._columns``), optionally a 1-D time array named
    ``timestamps``/``times``/``time``/``t`` (seconds), ``time_ms`` (milliseconds) or
    ``frame`` (frame numbers, used with a ``rate`` hint), and a 1-D ``modes``/``labels``
    array naming the columns; supply what it lacks as hints.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    mmap : bool
        Memory-map the coefficients (uncompressed members only) instead of reading.
    dataset : str, optional
        Name of the array holding the coefficients in a foreign file with several
        2-D arrays (the error lists them).
    **hints
        ``rate``, ``timestamps``, ``modes``, ``convention``, ``units``, ``wavelength``,
        ``metadata``, ``nonfinite``, ``start_time``, ``transpose``: fill what the file
        lacks; a hint contradicting the file raises ``ValueError``.

    Returns
    -------
    ModalLog
        The log.

    Raises
    ------
    FileNotFoundError, IsADirectoryError
        ``path`` is not a file.
    LogFormatError
        Corrupted, truncated or unexpected content (a ``ValueError``).
    """
    path = as_path(path)
    check_readable(path)
    with reading("NPZ", path):
        with zipfile.ZipFile(path) as zf:
            _check_entry_count(path, zf)
            names = {n[:-4] if n.endswith(".npy") else n: n for n in zf.namelist()}
            foreign = not ("header" in names and "coefficients" in names)
            if foreign and dataset is None and "header" in names:
                _refuse_orphan_header(zf, names, path)
            if not foreign:
                if dataset is not None and dataset != "coefficients":
                    raise _LogFormatError(
                        f"NPZ file {quoted(path)} was written by modalinfo; its coefficients are "
                        f"'coefficients', not {dataset!r}"
                    )
                text = _read_member(zf, names["header"])
                if text.dtype.kind != "U" or text.shape != ():
                    raise ValueError("member 'header' is not a string")
                header = parse_header(str(text[()]), "NPZ", path)
                coeffs = _mmap_member(path, zf, names["coefficients"]) if mmap else None
                if coeffs is None:
                    coeffs = _read_member(zf, names["coefficients"])
                check_stored_coefficients(coeffs, header, "NPZ", path)
                stored = stored_from_header(header)
                if header["has_timestamps"]:
                    if "timestamps" not in names:
                        raise ValueError("header announces timestamps but the member is missing")
                    stored["timestamps"] = _read_member(zf, names["timestamps"])
            else:
                arrays = {}
                for short, full in names.items():
                    arr = _mmap_member(path, zf, full) if mmap else None
                    arrays[short] = _read_member(zf, full) if arr is None else arr
                coeffs, stored = _foreign(arrays, path, dataset)
    return build_log(coeffs, path, stored, hints, foreign=foreign)


def _foreign(
    arrays: dict[str, np.ndarray], path: Path, dataset: str | None = None
) -> tuple[np.ndarray, dict]:
    two_d = {k: a for k, a in arrays.items() if a.ndim == 2 and a.dtype.kind in "fiu"}
    if dataset is None and not two_d:
        per_mode = mode_arrays(arrays)
        if per_mode is not None:  # one 1-D array per mode: z2, z3, ...
            names, columns = per_mode
            meta = {"source_file": path.name, "source_format": "npz"}
            stored = {"metadata": meta}
            stored["modes"], stored["convention"], assumed = mode_columns(names)
            if assumed:
                stored["_convention_assumed"] = True
            time_arrays(arrays, stored, meta)
            _units_member(arrays, stored)
            _rate_member(arrays, stored)
            return float_columns(columns, names, path), stored
    if dataset is not None:
        if dataset not in arrays:
            raise _LogFormatError(
                f"NPZ file {quoted(path)} has no array {dataset!r}; it holds "
                f"{', '.join(sorted(arrays)) or 'none'}"
            )
        if dataset not in two_d:
            raise _LogFormatError(
                f"NPZ file {quoted(path)}: array {dataset!r} is not a 2-D numeric array "
                f"(shape {arrays[dataset].shape}, dtype {arrays[dataset].dtype})"
            )
        key = dataset
    else:
        named = [k for k in _COEFF_NAMES if k in two_d]
        if len(named) > 1:
            # 'coeffs' beside 'coefficients' (two instruments' logs, or a raw and a
            # cleaned copy): the first name of the list was read without a word
            # (adversarial round 29 PART b, M13), as HDF5 refuses the same choice
            raise _LogFormatError(
                f"NPZ file {quoted(path)} has no modalinfo header and {len(named)} arrays named "
                f"as coefficients ({', '.join(sorted(named))}); pick one with dataset= "
                "(command line: --dataset NAME)"
            )
        if named:
            key = named[0]
        elif len(two_d) == 1:
            key = next(iter(two_d))
        elif not two_d and (cubes := sorted(k for k, a in arrays.items()
                                            if a.ndim == 3 and a.dtype.kind in "fiu")):
            # "0 2-D numeric arrays (none); pick one with dataset=" named no way out (fix56-c)
            first = arrays[cubes[0]]
            raise _LogFormatError(
                f"NPZ file {quoted(path)} has no 2-D numeric array; its array {cubes[0]!r} "
                f"is a 3-D {first.dtype} array of shape {first.shape}"
                + (f" (and {len(cubes) - 1} more 3-D)" if len(cubes) > 1 else "") + ": "
                + _CUBE_WORDS.format(*first.shape))
        else:
            raise _LogFormatError(
                f"NPZ file {quoted(path)} has no modalinfo header and {len(two_d)} 2-D numeric "
                f"arrays ({', '.join(sorted(two_d)) or 'none'}); pick one with dataset= "
                "(command line: --dataset NAME)"
            )
    meta: dict[str, Any] = {"source_file": path.name, "source_format": "npz"}
    if dataset is not None or len(two_d) > 1:  # which of several arrays was read
        meta["source_dataset"] = key
    stored: dict[str, Any] = {"metadata": meta}
    time_arrays(arrays, stored, meta)
    for name in ("modes", "labels", "columns", "mode_names"):
        names = arrays.get(name)
        if (names is not None and names.ndim == 1 and names.dtype.kind in "USiu"
                and names.shape[0] not in two_d[key].shape):
            stored["_bad_modes"] = (f"its member {name!r} lists {names.shape[0]} mode(s) for "
                                    f"data of shape {two_d[key].shape}")
            break
        if (
            names is not None
            and names.ndim == 1
            and names.dtype.kind in "USiu"
            and names.shape[0] == two_d[key].shape[1]
        ):
            text = [v.decode("utf-8", "replace") if isinstance(v, bytes) else str(v)
                    for v in names.tolist()]
            stored["modes"], stored["convention"], assumed = mode_columns(text)
            if assumed:
                stored["_convention_assumed"] = True
            break
    _units_member(arrays, stored)
    _rate_member(arrays, stored)
    return two_d[key], stored


def _rate_member(arrays: dict[str, np.ndarray], stored: dict) -> None:
    """Keep a foreign archive's rate member (never read: the note of ``build_log``)."""
    field = rate_field(arrays, "member")
    if field is not None:
        stored["_rate_field"] = field


def _units_member(arrays: dict[str, np.ndarray], stored: dict) -> None:
    """Record the units a foreign archive's ``units`` / ``unit`` member (0-d str) states."""
    for name in ("units", "unit"):
        if name in arrays:
            unit = unit_text(arrays[name])
            if unit is not None:
                stored["_unit"] = (unit, f"member {name!r}")
            return


def _refuse_cube(path: Path, shape: tuple[int, ...], dtype: np.dtype) -> None:
    """Refuse a 3-D array, a frame cube (frames x ny x nx), before reading its data.

    It was "the data must be 2-D (T frames, M modes); got 3-D ... (a single mode's
    series needs shape (T, 1): one column)", advice for another mistake (adversarial
    round 54 PART b; fix56-c). A cube of images is named as one, with the step it needs.
    """
    if len(shape) != 3:
        return
    raise _LogFormatError(f"{quoted(path)} holds a 3-D {dtype} array of shape {shape}: "
                          + _CUBE_WORDS.format(*shape))


#: What a 3-D array given as a log is, and the step it needs (``.format(n, ny, nx)``)
_CUBE_WORDS = (
    "a cube of images ({0} frames of {1} x {2} pixels, or {2} frames of {0} x {1}), not a "
    "log of modal coefficients, which is 2-D (frames x modes); fit the modes to each frame "
    "first (phase maps: `ModalBasis.project` of `modalinfo.bases`; WFS or camera images "
    "need their reconstruction) and save the (frames, modes) coefficients with numpy.save")


@unwrap
def read_npy(path, *, mmap: bool = False, **hints) -> ModalLog:
    """Read a plain ``.npy`` array ``(T, M)`` as a log, with hints for what it lacks.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    mmap : bool
        Memory-map the array (``numpy.load(mmap_mode="r")``) instead of reading it:
        a log larger than memory can then be summarised chunk by chunk.
    **hints
        ``rate``, ``timestamps``, ``modes``, ``convention``, ``units``,
        ``wavelength``, ``metadata``, ``nonfinite``, ``start_time``.

    Returns
    -------
    ModalLog
        The log (``metadata`` records the source file).

    Raises
    ------
    LogFormatError
        Bad magic or header, object dtype, or a file shorter (or longer) than the
        header declares: a truncated file is never read partially.
    """
    path = as_path(path)
    check_readable(path)
    with reading("NPY", path):
        with open(path, "rb") as fh:
            shape, fortran, dtype = _npy_header(fh)
            _check_dtype(dtype, "the array")
            _refuse_cube(path, shape, dtype)
            offset = fh.tell()
            need = _nbytes(shape, dtype)
            size = path.stat().st_size
            if size != offset + need:
                raise ValueError(
                    f"header declares {need} data bytes for shape {shape} {dtype} "
                    f"but the file holds {size - offset}"
                    + (" (truncated)" if size < offset + need else "")
                )
            if mmap and need:
                coeffs = np.memmap(
                    path,
                    dtype=dtype,
                    mode="r",
                    offset=offset,
                    shape=shape,
                    order="F" if fortran else "C",
                )
            else:
                count = int(np.prod(shape, dtype=np.int64))
                coeffs = np.fromfile(fh, dtype=dtype, count=count)
                if coeffs.size != count:  # shortened by another process since the check
                    raise ValueError(
                        f"header declares {need} data bytes for shape {shape} {dtype} but "
                        f"only {coeffs.size * dtype.itemsize} could be read (truncated "
                        "while it was read; another process may still be writing it)"
                    )
                coeffs = coeffs.reshape(shape, order="F" if fortran else "C")
    stored = {"metadata": {"source_file": path.name, "source_format": "npy"}}
    return build_log(coeffs, path, stored, hints, foreign=True)
