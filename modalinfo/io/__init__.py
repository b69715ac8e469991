"""Readers and writers of telemetry logs: NPZ, CSV, FITS, HDF5, AOT (lossless) and NPY (read).

``save(log, path)`` writes any ``ModalLog`` so that ``load(path)`` gives it back
exactly: bitwise coefficients (float32 or float64), timestamps or rate, modes,
convention, units, wavelength and metadata. Writes are atomic and never replace a
file unless ``overwrite=True``.

``load(path)`` takes the format from the file's content (magic bytes) or else its
extension, and also opens files written by other software (a plain 2-D array in
NPY/NPZ, a numeric CSV, a FITS image or table, an HDF5 file with one 2-D dataset);
``**hints`` supply what such files lack (``rate=``, ``units=``, ``modes=``, ...).

A FITS file whose primary header has ``AOT-VERS`` is AOT (Adaptive Optics Telemetry,
read and written with ``aotpy``): ``load`` returns one control loop, chosen with
``loop=UID`` when there are several (``modalinfo.io.aot``).

Errors: ``FileNotFoundError`` / ``IsADirectoryError`` / ``FileExistsError``
(``OSError``) for paths; :class:`LogFormatError` (a ``ValueError``) naming the file
for truncated, corrupted or unusable content; ``ValueError`` / ``TypeError`` for
bad hints or invalid log content (e.g. NaN with ``nonfinite="raise"``).

Warnings: ``LayoutWarning`` (a ``UserWarning``) where a foreign array was read frames x
modes because nothing said otherwise but its content says modes x frames
(``modalinfo.telemetry.checks.layout_doubt``); ``transpose=True`` reads it the other way
round, ``transpose=False`` keeps the layout without the warning.
"""

from __future__ import annotations

from pathlib import Path

from modalinfo.common.files import as_path, atomic_write, check_readable, quoted
from modalinfo.common.memory import usable_memory_bytes
from modalinfo.io._common import HINTS
from modalinfo.io.aot import read_aot, write_aot
from modalinfo.io.csv import read_csv, write_csv
from modalinfo.io.files import LogFormatError
from modalinfo.io.fits import read_fits, write_fits
from modalinfo.io.formats import (
    FORMATS,
    READ_ONLY_EXTENSIONS,
    detect_format,
    format_from_extension,
    format_hint,
)
from modalinfo.io.hdf5 import read_hdf5, write_hdf5
from modalinfo.io.integrity import IntegrityCheck, integrity_check
from modalinfo.io.npz import read_npy, read_npz, write_npz
from modalinfo.telemetry.checks import LayoutWarning
from modalinfo.telemetry.log import ModalLog

__all__ = [
    "FORMATS",
    "MAP_ABOVE",
    "HINTS",
    "IntegrityCheck",
    "LayoutWarning",
    "LogFormatError",
    "atomic_write",
    "integrity_check",
    "detect_format",
    "load",
    "mapping_pays",
    "save",
    "read_npz",
    "write_npz",
    "read_npy",
    "read_csv",
    "write_csv",
    "read_fits",
    "write_fits",
    "read_hdf5",
    "write_hdf5",
    "read_aot",
    "write_aot",
]


_READERS = {
    "npz": read_npz,
    "npy": read_npy,
    "csv": read_csv,
    "fits": read_fits,
    "hdf5": read_hdf5,
    "aot": read_aot,
}
_WRITERS = {
    "npz": write_npz, "csv": write_csv, "fits": write_fits, "hdf5": write_hdf5, "aot": write_aot
}


def _check_fmt(fmt, allowed) -> str:
    if not isinstance(fmt, str) or fmt.lower() not in allowed:
        raise ValueError(f"`fmt` must be one of {', '.join(allowed)}; got {fmt!r}.")
    return fmt.lower()


#: Largest log file the command lines read rather than memory-map [bytes] (also at most
#: 1/8 of the usable memory, see :func:`mapping_pays`). A mapped file truncated by
#: another process while a command reads it kills the command with SIGBUS, which Python
#: cannot catch (adversarial round 17 PART b, L07); a file read into memory is refused
#: as truncated instead. Up to 100 MB a plain read measured no cost in ``info`` beyond
#: the run-to-run noise (+0.1-0.3 s to read, and the log's size in memory); at 256 MB it
#: cost ~1.2 s more to read (Leftovers 18-sigint; benchmarks/RESULTS.md).
MAP_ABOVE = 128 * 2**20


def mapping_pays(path) -> bool:
    """Tell whether the command lines should memory-map this log rather than read it.

    Parameters
    ----------
    path : str or os.PathLike
        A log file (NPY, NPZ and HDF5 can be mapped; the answer is only about size).

    Returns
    -------
    bool
        True when the file is larger than ``min(MAP_ABOVE, usable memory / 8)``
        [bytes] (``modalinfo.common.memory.usable_memory_bytes``: the available memory
        or what an address-space limit leaves), i.e. when reading it whole would weigh
        on the memory; a smaller log is read (a truncation while it is read is then a
        refusal, not a SIGBUS: see :data:`MAP_ABOVE`). False for a path that cannot
        be read (the reader then says why).
    """
    try:
        size = as_path(path).stat().st_size
    except OSError:  # missing or unreadable: the reader says so in its own words
        return False
    return size > min(MAP_ABOVE, usable_memory_bytes() / 8)


def load(
    path,
    fmt: str | None = None,
    *,
    mmap: bool = False,
    verify: bool = True,
    dataset: str | None = None,
    **hints,
) -> ModalLog:
    """Read a telemetry log.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    fmt : {"npz", "npy", "csv", "fits", "hdf5", "aot"}, optional
        Force a format; by default it is detected from the content, then the
        extension.
    mmap : bool
        Memory-map the coefficients instead of reading them (NPY, uncompressed NPZ,
        contiguous HDF5); other formats are read in full. Use it for logs larger
        than memory with :func:`modalinfo.telemetry.summarize`.
    verify : bool
        Check the SHA-256 checksums that CSV and HDF5 files written by modalinfo
        carry (``False`` accepts a deliberately edited CSV). NPZ (CRC-32) and FITS
        (``DATASUM``) checksums are always verified (AOT: where the file has them). A
        memory-mapped coefficient array is not read here, so its checksum is not
        verified on loading:
        :func:`integrity_check` verifies it during a later pass over the data.
    dataset : str, optional
        HDF5 dataset path or NPZ array name of the coefficients, for a foreign file
        holding several 2-D arrays (the error lists them).
    **hints
        ``rate`` [Hz], ``timestamps`` [s], ``modes``, ``convention``, ``units``,
        ``wavelength`` [m], ``metadata``, ``nonfinite``, ``start_time`` [s]: supply
        what a foreign file lacks. A hint contradicting the file raises
        ``ValueError``, except for a foreign file's column names (``modes`` /
        ``convention`` relabel them) and timestamps (an explicit ``rate`` replaces
        timestamps that disagree with it); both are recorded in the metadata.
        ``loop`` (AOT only): uid of the control loop to read.
        ``transpose``: ``True`` reads a foreign array stored modes x frames,
        ``False`` keeps it as stored; by default an array that looks transposed
        (far more columns than rows) raises :class:`LogFormatError`, unless the file
        annotates its axes (FITS ``CTYPEn``, HDF5 attributes).

    Values a foreign file does not record and no hint gives (units ``rad``,
    convention ``noll``, modes after piston) are listed in ``metadata["assumed"]``.

    Returns
    -------
    ModalLog
        The log.

    Raises
    ------
    FileNotFoundError, IsADirectoryError
        ``path`` is not a file.
    LogFormatError
        Truncated, corrupted or unusable content (a ``ValueError``).
    ValueError, TypeError
        Bad ``fmt`` or hints, or content that is not a valid log.
    """
    path = as_path(path)
    if fmt is not None:
        fmt = _check_fmt(fmt, FORMATS)
    check_readable(path)
    if fmt is None:
        fmt = detect_format(path)
    options: dict = {}
    if fmt != "aot" and hints.pop("loop", None) is not None:
        raise ValueError(f"`loop` selects a control loop of an AOT file; {quoted(path)} is {fmt}.")
    if dataset is not None:
        # FITS too: its HDU, by index or EXTNAME (a thumbnail in the primary HDU hid the
        # log in HDU 1 from every command: adversarial round 10 PART b, rows F03, F04)
        if fmt not in ("npz", "hdf5", "fits"):
            raise ValueError(
                f"dataset={dataset!r} (command line: --dataset) applies only to HDF5, NPZ "
                f"and FITS files; {quoted(path)} is {fmt.upper()}"
            )
        if not isinstance(dataset, str) or not dataset.strip("/"):
            raise TypeError(f"`dataset` must be a non-empty str; got {dataset!r}.")
        options["dataset"] = dataset
    if mmap and fmt in ("npz", "npy", "hdf5"):
        options["mmap"] = True
    if fmt in ("csv", "hdf5", "aot"):
        options["verify"] = bool(verify)
    try:
        return _READERS[fmt](path, **options, **hints)
    except LogFormatError as exc:
        # the one place a reader is chosen: name what the content looks like when the
        # reader the name or ``fmt`` picked refuses it (round 18 PART b, row M02)
        hint = format_hint(path, fmt)
        if not hint:
            raise
        raise LogFormatError(f"{exc}; {hint}") from exc


def save(log: ModalLog, path, fmt: str | None = None, overwrite: bool = False) -> Path:
    """Write a log losslessly (atomic; never replaces a file unless asked).

    Parameters
    ----------
    log : ModalLog
        The log.
    path : str or os.PathLike
        Target file.
    fmt : {"npz", "csv", "fits", "hdf5", "aot"}, optional
        Format; by default from the extension of ``path`` (``.fits`` is our FITS
        layout; pass ``fmt="aot"`` for an AOT file).
    overwrite : bool
        Replace an existing file; otherwise ``FileExistsError`` naming it.

    Returns
    -------
    pathlib.Path
        The written path.
    """
    if not isinstance(log, ModalLog):
        raise TypeError(f"`log` must be a ModalLog; got {type(log).__name__}.")
    path = as_path(path)
    if fmt is None:
        fmt = format_from_extension(path)
        if fmt is None or path.suffix.lower() in READ_ONLY_EXTENSIONS:
            raise ValueError(
                f"cannot tell the format of {quoted(path)} from its extension; use .npz, .csv, "
                ".fits or .h5, or pass fmt= (npy cannot hold the metadata)."
            )
    else:
        fmt = _check_fmt(fmt, tuple(_WRITERS))
    if not isinstance(overwrite, bool):
        raise TypeError(f"`overwrite` must be a bool; got {overwrite!r}.")
    return _WRITERS[fmt](log, path, overwrite=overwrite)
