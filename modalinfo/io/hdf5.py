"""HDF5 logs (h5py): dataset ``coefficients`` plus attributes, optional ``timestamps``.

Layout written by :func:`write_hdf5`:

``/coefficients``
    ``(T, M)`` float32/float64, contiguous and uncompressed (so it can be
    memory-mapped), attributes ``units``, ``convention``, ``labels`` for people
    browsing the file;
``/timestamps``
    ``(T,)`` float64 seconds, only with explicit timestamps;
``/modalinfo_header``
    the JSON header (modes, metadata, ...) as a ``uint8`` dataset of ASCII bytes,
    including a SHA-256 of the data, verified on reading (HDF5 itself has no
    checksum on contiguous data).

Nothing is stored as a variable-length string: libhdf5 1.14 (through h5py)
crashes the interpreter with a segmentation fault when it reads a variable-length
string whose global-heap reference is damaged (found by flipping single bits of
test files), whereas damaged fixed-size data give an error or a checksum mismatch.

``mmap=True`` memory-maps a contiguous, unfiltered dataset straight from the file
(its byte offset comes from h5py), after checking the file is long enough; the
checksum is then not verified (that would read everything). Chunked or compressed
datasets are read in full.

Foreign HDF5: the one 2-D numeric dataset of the file (or one named
``coefficients``/``coeffs``/``data``, or the one ``dataset=`` names), and a 1-D
time dataset if present: ``timestamps``/``times``/``time``/``t`` in seconds,
``time_ms`` in milliseconds, or any of them with a ``units`` attribute (``"s"``,
``"ms"``, ``"us"``, or CF's ``"milliseconds since 2026-06-01"``), converted to seconds;
``frame`` numbers need a ``rate`` hint; netCDF dimensions without a coordinate (datasets
of zeros) are not times. Column names come from a ``labels``/``modes``/``columns``
attribute of the dataset (``["z2", "z3", ...]``), a pandas ``to_hdf(format="fixed")``
frame's ``blockN_items`` (a ``time`` column among them is the time axis, a ``frame``
column beside it dropped; two time columns are refused) or a netCDF
string coordinate attached to the column axis; a file of 1-D datasets ``z2``, ``z3``, ...
(one per mode) is read as their columns. CF packing (``scale_factor`` / ``add_offset``)
and fill values are applied; a lossy scale-offset filter is said
(``metadata["lossy_storage"]``); rows of a chunked dataset never written, pandas tables
(``format="table"``) are refused.
An axis annotation (attribute ``axes``/``dims``/``dimension_labels`` such as
``["mode", "time"]``, attribute ``layout="modes_first"``, or dimension-scale
labels) is followed: a modes x frames dataset is read transposed and
``metadata["layout"]`` says so. Supply the rest as hints.
"""

from __future__ import annotations

import errno
import io
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from modalinfo.common.files import as_path, atomic_write, check_readable, quoted, shell_quoted
from modalinfo.io._columns import (
    float_columns,
    mode_arrays,
    mode_columns,
    set_timestamps,
    time_arrays,
    time_kind,
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
    verify_checksum,
)
from modalinfo.io._foreign import axis_layout, rate_field
from modalinfo.io.files import LogFormatError
from modalinfo.telemetry.log import ModalLog
from modalinfo.telemetry.scan import scan_rows

__all__ = ["read_hdf5", "write_hdf5", "read_log_group", "write_log_group", "write_hdf5_file"]

_HEADER = "modalinfo_header"
_COEFF_NAMES = ("coefficients", "coeffs", "coefs", "data")


def write_hdf5(log: ModalLog, path, *, overwrite: bool = False) -> Path:
    """Write ``log`` to an HDF5 file, atomically.

    The file is built in memory and its bytes written at once (a log whose arrays do
    not fit in memory is written by HDF5 on disk): a disk that fills mid-write ends in
    one ``OSError`` naming ``path`` (errno ``ENOSPC``), the old file intact and no
    temporary file left, where h5py's failed close once ended the interpreter with a
    segmentation fault.

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

    nbytes = log.coeffs.nbytes + (0 if log.timestamps is None else log.timestamps.nbytes)
    return write_hdf5_file(path, lambda f: write_log_group(f, log), overwrite=overwrite,
                           nbytes=nbytes)


#: Memory an in-memory HDF5 file takes while ``write_hdf5_file`` builds and writes it,
#: in copies of its datasets' bytes: the ``io.BytesIO`` the file is built in, grown by
#: reallocation. Measured peaks over the resident set (docs/ADVERSARIAL.md, "Leftovers
#: 14-h5"): 1.01 for a 385 MiB run file, 1.3-1.4 for 2.5-10 MiB ones; rounded up.
IMAGE_COPIES = 2.0


def image_bytes(nbytes: float) -> float:
    """Memory ``write_hdf5_file`` adds while it builds a file in memory [bytes].

    ``IMAGE_COPIES`` times the datasets' bytes ``nbytes``; the one rule both the writer
    (which builds on disk when this exceeds the memory it may still allocate) and the
    estimates of a run that saves its result (``closedloop.resources.estimate(...,
    save=True)``) use.
    """
    return IMAGE_COPIES * float(nbytes)


def write_hdf5_file(path, fill: Callable[[Any], None], *, overwrite: bool = False,
                    nbytes: float = 0.0) -> Path:
    """Write the HDF5 file that ``fill`` builds, atomically; a full disk is one error.

    The file is built in memory (an ``io.BytesIO`` that h5py writes through) and its
    bytes go to disk through ``modalinfo.common.files.atomic_write``, so HDF5 never
    writes to the disk itself. Written by name on disk, a disk that filled as HDF5
    flushed its metadata on closing made h5py's close fail ("Can't decrement id ref
    count" naming the temporary file), then the interpreter died of a segmentation
    fault, leaving the temporary file (left13-cli, left14-h5). Here a full disk raises
    the one ``OSError`` of ``atomic_write``: ``No space left on device writing 'PATH'
    (nothing was written)`` (or "the old file is unchanged"), errno ``ENOSPC``.

    A file whose datasets need more than the memory this process may still allocate
    (``image_bytes(nbytes)``, ``IMAGE_COPIES`` times ``nbytes``, against
    ``modalinfo.common.memory.usable_memory_bytes``) is written by h5py on disk, through
    a file object whose first failed write stops the work and whose later writes (those
    of HDF5's close) are dropped: the same one error, the staging file removed.

    Parameters
    ----------
    path : str or os.PathLike
        Target file.
    fill : callable
        ``fill(f)`` writes the content into ``f``, an ``h5py.File`` open for writing.
    overwrite : bool
        Replace an existing file; otherwise ``FileExistsError``.
    nbytes : float
        The datasets' bytes [bytes], for the memory rule above.

    Returns
    -------
    pathlib.Path
        The written path.
    """
    import h5py

    from modalinfo.common.memory import usable_memory_bytes

    path = as_path(path)
    if image_bytes(nbytes) > usable_memory_bytes():
        return atomic_write(path, lambda name: _write_on_disk(name, fill),
                            overwrite=overwrite, by_name=True)

    def write(fh) -> None:
        image = io.BytesIO()
        with h5py.File(image, "w") as f:
            fill(f)
        fh.write(image.getbuffer())  # no copy of the image

    return atomic_write(path, write, overwrite=overwrite)


class _GuardedFile(io.RawIOBase):
    """The staging file as h5py writes it on disk: a failed write never fails HDF5's close.

    While the file is filled, the first failed write raises (the fill stops there) and is
    kept; from then on, and while the file closes, writes are dropped: h5py's close then
    succeeds instead of failing in a deallocation and crashing (left14-h5). The kept
    error is raised once h5py let go of the file; the file is garbage then, removed by
    ``atomic_write``.
    """

    def __init__(self, fh) -> None:
        super().__init__()
        self.fh = fh
        self.error: OSError | None = None
        self.closing = False

    def readable(self) -> bool:
        return True

    def writable(self) -> bool:
        return True

    def seekable(self) -> bool:
        return True

    def readinto(self, buffer) -> int:
        return self.fh.readinto(buffer)

    def seek(self, offset: int, whence: int = 0) -> int:
        return self.fh.seek(offset, whence)

    def tell(self) -> int:
        return self.fh.tell()

    def truncate(self, size: int | None = None) -> int:
        if self.error is not None:
            return self.tell() if size is None else size
        try:
            return self.fh.truncate(size)
        except OSError as exc:
            return self._failed(exc, 0 if size is None else size)

    def write(self, data) -> int:
        view = memoryview(data).cast("B")
        if self.error is not None:
            return len(view)  # dropped: the file is discarded
        done = 0
        try:
            while done < len(view):  # a raw write may write less (a disk filling up)
                n = self.fh.write(view[done:])
                if not n:
                    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
                done += n
        except OSError as exc:
            return self._failed(exc, len(view))
        return done

    def _failed(self, exc: OSError, size: int) -> int:
        self.error = exc
        if self.closing:
            return size
        raise exc


def _write_on_disk(name: Path, fill: Callable[[Any], None]) -> None:
    """Let h5py write the file ``name`` through ``_GuardedFile`` (unbuffered)."""
    import h5py

    with open(name, "w+b", buffering=0) as fh:
        guarded = _GuardedFile(fh)
        try:
            f = h5py.File(guarded, "w")
        except (OSError, RuntimeError):  # h5py's words for our failed write: ours instead
            if guarded.error is not None:
                raise guarded.error from None
            raise
        try:
            fill(f)
        except (OSError, RuntimeError):  # as above
            if guarded.error is None:
                raise
        finally:
            guarded.closing = True
            f.close()
    if guarded.error is not None:
        raise guarded.error


def write_log_group(group, log: ModalLog) -> None:
    """Write ``log`` into an open ``h5py`` group, in :func:`write_hdf5`'s layout.

    The one HDF5 writer of a ``ModalLog``: :func:`write_hdf5` writes at a file's root,
    other files (e.g. a ``closedloop`` result) hold several logs, one group each.

    Parameters
    ----------
    group : h5py.Group
        An empty group (or file) open for writing.
    log : ModalLog
        The log.
    """
    if not isinstance(log, ModalLog):
        raise TypeError(f"`log` must be a ModalLog; got {type(log).__name__}.")
    header = dumps(log_header(log, checksum=True))
    dset = group.create_dataset("coefficients", shape=log.shape, dtype=log.dtype)
    rows = 0
    for block in log.iter_chunks(scan_rows(log.coeffs)):
        dset[rows : rows + block.shape[0]] = block
        rows += block.shape[0]
    # fixed-length byte strings: no variable-length heap references (see module doc)
    dset.attrs["units"] = np.bytes_(log.units)
    dset.attrs["convention"] = np.bytes_(log.convention)
    dset.attrs["labels"] = np.array([lab.encode("utf-8") for lab in log.labels])
    if log.timestamps is not None:
        group.create_dataset("timestamps", data=np.asarray(log.timestamps))
    group.create_dataset(_HEADER, data=np.frombuffer(header.encode("ascii"), dtype=np.uint8))


def read_log_group(group, path, *, verify: bool = True) -> ModalLog:
    """Read a log written by :func:`write_log_group` from an open ``h5py`` group.

    Parameters
    ----------
    group : h5py.Group
        The group (or file) holding the log.
    path : str or os.PathLike
        The file, for messages.
    verify : bool
        Check the recorded SHA-256 of the header, coefficients and timestamps.

    Returns
    -------
    ModalLog

    Raises
    ------
    LogFormatError
        A group without modalinfo's header, or a damaged one.
    """
    path = as_path(path)
    with reading("HDF5", path):
        if _HEADER not in group:
            raise LogFormatError(f"HDF5 file {quoted(path)}: group '{group.name}' holds no "
                                 "modalinfo log")
        coeffs, stored = _read_own(group, path, mmap=False, verify=verify, dataset=None)
    return build_log(coeffs, path, stored, {})


def _datasets(f) -> dict[str, Any]:
    import h5py

    found: dict[str, Any] = {}

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset):
            found[name] = obj

    f.visititems(visit)
    return found


def _link_note(f, key: str) -> str:
    """Say what ``key`` is when it is a link: links are not followed to a dataset.

    A soft link or an external link named with ``--dataset`` was reported as "no
    dataset" with no word of the link (round 11 PART b, H05 and H06).
    """
    import h5py

    try:
        link = f.get(key, getlink=True)
    except (KeyError, ValueError, OSError):
        return ""
    if isinstance(link, h5py.SoftLink):
        return f" (it is a link to {link.path!r}: name that path)"
    if isinstance(link, h5py.ExternalLink):
        return (f" (it is a link to {link.path!r} in another file, {link.filename!r}, "
                "not followed: read that file)")
    return ""


def _links(f) -> list[str]:
    """Paths of the soft and external links in ``f`` (a dangling one included)."""
    import h5py

    found: list[str] = []

    def visit(name, link):
        if isinstance(link, h5py.SoftLink | h5py.ExternalLink):
            found.append(name)

    f.visititems_links(visit)
    return found


def _check_virtual_sources(dset, path: Path) -> None:
    """Refuse a virtual dataset whose source files are missing.

    libhdf5 reads the missing part as the fill value without a word: a log of zeros
    (or NaN) where the data were (round 14 PART b, H04). A source named ``.`` is the
    file itself; others are looked up where libhdf5 looks (``HDF5_VDS_PREFIX``, beside
    the file, the working folder).
    """
    if not getattr(dset, "is_virtual", False):
        return
    import os

    # where libhdf5 looks: HDF5_VDS_PREFIX (${ORIGIN}: the file's folder), the file's
    # folder, the working folder
    folders = [Path(p.replace("${ORIGIN}", str(path.parent)))
               for p in os.environ.get("HDF5_VDS_PREFIX", "").split(os.pathsep) if p]
    folders += [path.parent, Path.cwd()]
    missing = sorted({
        vs.file_name for vs in dset.virtual_sources()
        if vs.file_name != "." and not any((f / vs.file_name).exists() for f in folders)
    })
    if missing:
        raise LogFormatError(
            f"HDF5 file {quoted(path)}: dataset {dset.name!r} is virtual and its source file(s) "
            f"{', '.join(repr(m) for m in missing)} are missing (libhdf5 would read that "
            "part as the fill value); put them beside the file")


def _load(dset, path: Path, mmap: bool) -> np.ndarray:
    if dset.dtype.kind not in "fiu":
        raise LogFormatError(
            f"HDF5 file {quoted(path)}: dataset {dset.name!r} has non-numeric dtype {dset.dtype}"
        )
    if mmap and dset.chunks is None and dset.compression is None and dset.size:
        offset = dset.id.get_offset()
        if offset is not None:
            dtype = dset.dtype
            need = int(dset.size) * dtype.itemsize
            if path.stat().st_size < offset + need:
                raise LogFormatError(
                    f"corrupt HDF5 file {quoted(path)}: dataset {dset.name!r} needs bytes "
                    f"{offset}..{offset + need} but the file has {path.stat().st_size} (truncated)"
                )
            return np.memmap(path, dtype=dtype, mode="r", offset=offset, shape=dset.shape)
    return dset[()]


@unwrap
def read_hdf5(
    path, *, mmap: bool = False, verify: bool = True, dataset: str | None = None, **hints
) -> ModalLog:
    """Read a log from an HDF5 file written by :func:`write_hdf5` or by other software.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    mmap : bool
        Memory-map a contiguous, uncompressed coefficient dataset instead of reading.
    verify : bool
        Check the SHA-256 recorded by :func:`write_hdf5`. With ``mmap`` the header
        and timestamps are checked on reading but the coefficients are not (that
        would read them all): :func:`modalinfo.io.integrity_check` verifies them
        during a later pass over the data (``modalinfo info`` does).
    dataset : str, optional
        Path of the coefficient dataset in a foreign file with several 2-D numeric
        datasets (the error lists them), e.g. ``"loop/modes"``.
    **hints
        ``rate``, ``timestamps``, ``modes``, ``convention``, ``units``, ``wavelength``,
        ``metadata``, ``nonfinite``, ``start_time``, ``transpose``.

    Returns
    -------
    ModalLog
        The log.

    Raises
    ------
    LogFormatError
        A file h5py cannot open, a truncated dataset, a checksum mismatch or no
        usable 2-D dataset.
    """
    import h5py

    path = as_path(path)
    check_readable(path)
    foreign = False
    with reading("HDF5", path):
        with h5py.File(path, "r") as f:
            group = f if _HEADER in f else _log_group(f, path, dataset)
            if group is f:
                coeffs, stored = _read_own(f, path, mmap, verify, dataset)
            elif group is not None:
                coeffs, stored = _read_own(group, path, mmap, verify, None)
                if f.attrs.get("format") == "closedloop-result":
                    _result_log(stored, group.name.strip("/"), path,
                                f.get(_TRANSIENT) if isinstance(f.get(_TRANSIENT),
                                                                h5py.Dataset) else None)
            else:
                foreign = True
                coeffs, stored = _foreign(f, path, mmap, dataset)
    return build_log(coeffs, path, stored, hints, foreign=foreign)


def _log_group(f, path: Path, dataset: str | None):
    """Return the group below the root holding a log of :func:`write_log_group`, else None.

    A log written into a group (``run1/``, as a file of several logs holds them) was
    called "corrupt" (its ``modalinfo_header`` sits beside its coefficients, not at the
    root), even when ``--dataset run1/coefficients`` named it as the refusal advised
    (adversarial round 25 PART b, H12-H15). One such group and no other 2-D numeric
    dataset named as coefficients (``_COEFF_NAMES``, the names ``_foreign`` picks by;
    review20: a second dataset of any name made the file "corrupt"): that group; one
    group and such a dataset: refused, naming both; ``dataset`` naming a group or its
    ``coefficients``: that group; several groups and no ``dataset``: refused, naming
    them. A closedloop result is read at the log ``dataset`` names (``logs/dm0.pol``, with
    or without ``/coefficients``); without one, or naming anything else, it keeps its own
    refusal (``_foreign``), which lists its logs.
    """
    groups = _own_groups(f)
    if f.attrs.get("format") == "closedloop-result":
        # its logs are complete modalinfo logs (write_log_group: rate, units, wavelength,
        # the run's config in the metadata), the same SimulationResult.load reads: the
        # README's "--dataset run1" read them, yet they were refused with the export
        # advice (adversarial round 54 PART b, P21)
        key = _group_key(dataset)
        return f[key] if key in groups else None
    if not groups:
        return None
    if dataset is not None:
        key = _group_key(dataset)
        return f[key] if key in groups else None
    inside = tuple(g + "/" for g in groups)
    # other 2-D datasets named as coefficients compete with the group, as in ``_foreign``;
    # any other one (a reconstructor, an image) does not: the file was called "corrupt"
    others = [k for k, d in _datasets(f).items()
              if d.ndim == 2 and d.dtype.kind in "fiu" and not k.startswith(inside)
              and k.rsplit("/", 1)[-1].lower() in _COEFF_NAMES]
    if len(groups) == 1 and not others:
        return f[groups[0]]
    if len(groups) == 1:
        raise LogFormatError(
            f"HDF5 file {quoted(path)} holds a modalinfo log in group {groups[0]} and other "
            f"coefficients ({', '.join(sorted(others))}); pick one with dataset= (command "
            f"line: --dataset {groups[0]})")
    if len(groups) > 1:
        raise LogFormatError(
            f"HDF5 file {quoted(path)} holds {len(groups)} modalinfo logs, in groups "
            f"{', '.join(sorted(groups))}; pick one with dataset= (command line: "
            f"--dataset {sorted(groups)[0]})")
    return None


#: The dataset of a closedloop result holding its closure transient [frames]
#: (``closedloop.result.TRANSIENT_DATASET``, named here: modalinfo never imports closedloop)
_TRANSIENT = "transient_frames"


def _result_log(stored: dict, key: str, path: Path, transient=None) -> None:
    """Describe a closedloop result's log as its AOT export does, or refuse its residual.

    The log's header holds the run's config and ``quantity`` (residual, pol, commands):
    ``loop`` (closed or open) and ``coefficient_quantity`` are set from them, the words
    the AOT reader takes from the export's cards, so ``info`` says "pseudo-open-loop
    coefficients" here too. A closed loop's residual and commands get their closure
    transient (the frames before the steady state, which the quality pass leaves out
    rather than flag as glitches) in ``metadata["transient_frames"]`` from the result's
    dataset ``transient`` (``transient_frames``, written by ``SimulationResult.save``
    since fix56-c), as the export's ``MI_TRANS`` card (fix54-e); those of a result saved
    before it are refused: this reader, below closedloop, cannot tell their transient.
    """
    meta = dict(stored.get("metadata") or {})
    config = meta.get("config") if isinstance(meta.get("config"), dict) else {}
    loop = config.get("loop") if isinstance(config.get("loop"), dict) else {}
    closed = loop.get("closed", True) is not False  # the config omits the default, closed
    quantity = meta.get("quantity")
    value = None
    if transient is not None and transient.shape == () and transient.dtype.kind in "iu":
        value = int(transient[()])
    if quantity in ("residual", "commands") and closed and value is not None:
        meta["transient_frames"] = value
    elif quantity in ("residual", "commands") and closed:
        dm = key.rsplit("/", 1)[-1].split(".", 1)[0]
        route = (f"export the result with `closedloop export {shell_quoted(path.name)} "
                 f"OUT.fits` and read OUT.fits with --loop {dm}" if quantity == "residual"
                 else f"read them in Python, closedloop.SimulationResult.load(path)"
                      f".logs[{key.rsplit('/', 1)[-1]!r}], from its averaging_start")
        raise LogFormatError(
            f"HDF5 file {quoted(path)}: {key!r} holds the {quantity} of a closed loop, whose "
            "closure transient (the frames before the steady state, which the quality pass "
            "must leave out) only closedloop can tell: "
            f"{route}; the pseudo-open-loop log is read here (--dataset "
            f"{key.rsplit('.', 1)[0]}.pol)")
    meta.setdefault("loop", "closed" if closed else "open")
    if isinstance(quantity, str) and quantity:
        meta.setdefault("coefficient_quantity", quantity)
    meta.setdefault("source_dataset", key)
    stored["metadata"] = meta


def _own_groups(f) -> list[str]:
    """Paths of the groups below ``f`` holding a log of :func:`write_log_group`."""
    import h5py

    groups: list[str] = []
    f.visititems(lambda name, obj: groups.append(name) if isinstance(obj, h5py.Group)
                 and _HEADER in obj and "coefficients" in obj else None)
    return groups


def _group_key(dataset: str | None) -> str | None:
    """Return the group path ``dataset`` names (``run1`` or ``run1/coefficients``: ``run1``)."""
    if dataset is None:
        return None
    key = dataset.strip("/")
    return key[: -len("/coefficients")] if key.endswith("/coefficients") else key


def _read_own(f, path: Path, mmap: bool, verify: bool,
              dataset: str | None) -> tuple[np.ndarray, dict]:
    """Coefficients and stored values of a log written by :func:`write_log_group`."""
    raw = f[_HEADER]
    if raw.dtype != np.uint8 or raw.ndim != 1:
        raise LogFormatError(f"corrupt HDF5 file {quoted(path)}: bad {_HEADER} dataset")
    text = raw[()].tobytes().decode("ascii")
    header = parse_header(text, "HDF5", path, verify=verify)
    if "coefficients" not in f:
        raise LogFormatError(f"corrupt HDF5 file {quoted(path)}: no coefficients dataset")
    coeffs = _load(f["coefficients"], path, mmap)
    check_stored_coefficients(coeffs, header, "HDF5", path)
    _check_own_attributes(f["coefficients"], header, path)
    stored = stored_from_header(header)
    if header["has_timestamps"]:
        if "timestamps" not in f:
            raise LogFormatError(f"corrupt HDF5 file {quoted(path)}: timestamps missing")
        stored["timestamps"] = f["timestamps"][()]
        if stored["timestamps"].dtype.str != "<f8":
            raise LogFormatError(
                f"corrupt HDF5 file {quoted(path)}: timestamps have dtype "
                f"{stored['timestamps'].dtype.str}, expected <f8"
            )
    if verify and header["has_timestamps"]:
        verify_checksum(header, "timestamps", stored["timestamps"], "HDF5", path)
    if verify and not isinstance(coeffs, np.memmap):
        verify_checksum(header, "coefficients", coeffs, "HDF5", path)
    if dataset is not None and dataset.strip("/") != "coefficients":
        raise LogFormatError(
            f"HDF5 file {quoted(path)} was written by modalinfo; its coefficients are "
            f"'coefficients', not {dataset!r}"
        )
    return coeffs, stored


def _check_own_attributes(dset, header: dict, path: Path) -> None:
    """Refuse a log whose ``units`` / ``convention`` / ``labels`` attributes contradict its header.

    :func:`write_log_group` writes them for other tools (HDFView, h5py) from the header;
    the header's checksum does not cover them, so an edit in another tool (``units``
    set to 'nm' on a log in rad, relabelled modes) was read as the header said without
    a word (round 19 PART b, B13-B14).
    """
    from modalinfo.telemetry.checks import mode_labels

    def text(value) -> str:
        return value.decode("utf-8", "replace") if isinstance(value, bytes) else str(value)

    attrs = dset.attrs
    for key in ("units", "convention"):
        if key in attrs and key in header and text(attrs[key]) != str(header[key]):
            raise LogFormatError(
                f"corrupt HDF5 file {quoted(path)}: attribute {key}={text(attrs[key])!r} of "
                f"'coefficients' contradicts the header's {header[key]!r} (edited after "
                "modalinfo wrote it?): set the attribute back to the header's value, or "
                "rewrite the log with the right one")
    if "labels" in attrs and "modes" in header and "convention" in header:
        try:
            stored = [text(v) for v in np.asarray(attrs["labels"]).ravel()]
            expected = mode_labels(header["modes"], header["convention"])
        except (TypeError, ValueError):
            return
        if stored != list(expected):
            raise LogFormatError(
                f"corrupt HDF5 file {quoted(path)}: attribute labels of 'coefficients' "
                f"({', '.join(stored[:3])}{', ...' if len(stored) > 3 else ''}) contradict "
                f"the header's modes ({', '.join(expected[:3])}"
                f"{', ...' if len(expected) > 3 else ''}) (edited after modalinfo wrote it?)")


def _foreign(f, path: Path, mmap: bool, dataset: str | None) -> tuple[np.ndarray, dict]:
    if f.attrs.get("format") == "closedloop-result":
        # a simulation's result holds several logs: one is read where dataset names it
        # (``_log_group``); here none is named, or something else is. A foreign read of
        # --dataset logs/dm0.pol/coefficients was "corrupt" and would lose the rate and
        # wavelength (audit 10, feedback, row cli-h5-result-dataset)
        logs = sorted(_own_groups(f))
        named = (f"; {dataset!r} is not one of its logs" if dataset is not None
                 else ", not a log")
        pol = next((g for g in logs if g.endswith(".pol")), logs[0] if logs else None)
        read = (f"read its pseudo-open-loop log with dataset= (command line: --dataset {pol}; "
                f"its logs: {', '.join(logs)}), or " if logs else "")
        raise LogFormatError(
            f"HDF5 file {quoted(path)} is a closedloop result{named}: {read}export its logs "
            f"with `closedloop export {shell_quoted(path.name)} OUT.fits` and read OUT.fits "
            "with --loop (Python: closedloop.SimulationResult.load(path).logs)")
    if dataset is None:
        table = _pandas_data_columns(f, path)
        if table is not None:
            return table
    dsets = _datasets(f)
    two_d = {k: d for k, d in dsets.items() if d.ndim == 2 and d.dtype.kind in "fiu"}
    if dataset is None and not two_d:
        per_mode = mode_arrays(dsets)
        if per_mode is not None:  # one 1-D dataset per mode: z2, z3, ...
            names, columns = per_mode
            meta = {"source_file": path.name, "source_format": "hdf5"}
            stored: dict[str, Any] = {"metadata": meta}
            short = [n.rsplit("/", 1)[-1] for n in names]
            stored["modes"], stored["convention"], assumed = mode_columns(short)
            if assumed:
                stored["_convention_assumed"] = True
            time_arrays(dsets, stored, meta)
            stated = {_stated_unit(c.attrs) for c in columns}
            if len(stated) > 1:
                raise LogFormatError(
                    f"HDF5 file {quoted(path)}: the per-mode datasets' units attributes disagree "
                    f"({', '.join(sorted(str(u) for u in stated))}); one log holds one unit"
                )
            unit = stated.pop() or _nesting_unit(columns[0], "")[0]
            if unit is not None:
                stored["_unit"] = (unit, "units attribute")
            _rate_fields(stored, (dsets, "dataset"), (f.attrs, "file attribute"))
            stacked = float_columns(columns, short, path)
            for k, column in enumerate(columns):
                stacked[:, k] = _unpacked(_missing_as_nan(stacked[:, k], column.attrs),
                                          column.attrs, meta, column.name)
            return stacked, stored
    if dataset is not None:
        key = dataset.strip("/")
        if key not in dsets:
            raise LogFormatError(
                f"HDF5 file {quoted(path)} has no dataset {dataset!r}{_link_note(f, key)}; its 2-D "
                f"numeric datasets: {', '.join(sorted(two_d)) or 'none'}"
            )
        if key not in two_d:
            raise LogFormatError(
                f"HDF5 file {quoted(path)}: dataset {dataset!r} is not a 2-D numeric array "
                f"(shape {dsets[key].shape}, dtype {dsets[key].dtype})"
            )
    else:
        named = [k for k in two_d if k.rsplit("/", 1)[-1].lower() in _COEFF_NAMES]
        if len(named) == 1:
            key = named[0]
        elif len(two_d) == 1:
            key = next(iter(two_d))
        elif not two_d:
            _refuse_pandas_table(f, path)
            # "pick one with --dataset" among none, when the data sit behind a link that
            # is not followed (round 14 PART b, H01-H03): name the links instead
            notes = [f"{name!r}{_link_note(f, name)}" for name in _links(f)]
            raise LogFormatError(
                f"HDF5 file {quoted(path)} has no modalinfo header and no 2-D numeric dataset"
                + (f"; it holds links: {', '.join(notes)}" if notes else "")
            )
        else:
            _refuse_pandas_table(f, path)
            raise LogFormatError(
                f"HDF5 file {quoted(path)} has no modalinfo header and {len(two_d)} 2-D numeric "
                f"datasets ({', '.join(sorted(two_d))}); pick one with dataset= "
                "(command line: --dataset PATH)"
            )
    dset = two_d[key]
    _check_virtual_sources(dset, path)
    if "convention" in dset.attrs and "labels" in dset.attrs:
        raise LogFormatError(
            f"corrupt HDF5 file {quoted(path)}: dataset {key!r} was written by modalinfo "
            f"but the file's {_HEADER!r} dataset is missing"
        )
    _refuse_unwritten_rows(dset, path)
    meta: dict[str, Any] = {"source_file": path.name, "source_format": "hdf5"}
    coeffs = _unpacked(_missing_as_nan(_load(dset, path, mmap), dset.attrs), dset.attrs, meta,
                       key)
    if dataset is not None or len(two_d) > 1:
        meta["source_dataset"] = key
    _lossy_filter(dset, key, meta)
    stored: dict[str, Any] = {"metadata": meta}
    time_arrays(dsets, stored, meta)
    names = _column_names(dset)
    if names is None:
        names = _pandas_items(f, key, dset)
    if names is None:
        names = _scale_labels(dset)
    if names is not None and len(names) == coeffs.shape[1] > 1:
        coeffs, names = _time_column(coeffs, names, stored, meta, path, key)
    if names is not None and len(names) not in dset.shape and len(names) not in coeffs.shape:
        stored["_bad_modes"] = (f"the column-name attribute of {key!r} lists {len(names)} "
                                f"mode(s) for data of shape {dset.shape}")
    if names is not None and len(names) == coeffs.shape[1]:
        stored["modes"], stored["convention"], assumed = mode_columns(names)
        if assumed:
            stored["_convention_assumed"] = True
    layout = _annotation(dset)
    if layout is not None:
        stored["_layout"] = layout
    elif "MATLAB_class" in dset.attrs:
        # MATLAB (v7.3 MAT-file) stores arrays column-major: a T x M matrix arrives as
        # (M, T); a 300 x 200 one was read as 200 frames of 300 modes without a word
        # (round 31 PART b, a23, a42)
        stored["_column_major"] = (
            f"dataset {key!r} is a MATLAB variable (attribute MATLAB_class), stored "
            "column-major: a MATLAB T x M matrix arrives as M x T")
    unit, where = _stated_unit(dset.attrs), key
    if unit is None:
        unit, where = _nesting_unit(dset, key)
    if unit is not None:
        stored["_unit"] = (unit, f"units attribute of {where!r}")
    _rate_fields(stored, (dsets, "dataset"), (dset.attrs, f"attribute of {key!r},"),
                 (f.attrs, "file attribute"))
    return coeffs, stored


def _rate_fields(stored: dict, *places) -> None:
    """Keep the first rate field of ``places`` (never read: the note of ``build_log``)."""
    for fields, where in places:
        field = rate_field(fields, where)
        if field is not None:
            stored["_rate_field"] = field
            return


def _missing_as_nan(values: np.ndarray, attrs) -> np.ndarray:
    """Return ``values`` with the cells a CF ``_FillValue`` / ``missing_value`` marks as NaN.

    netCDF-4 files are HDF5 files: their missing cells hold the fill value (-9999, say),
    read as a coefficient before (audit 9-files); NaN lets the nonfinite policy act.
    """
    marks = []
    for name in ("_FillValue", "missing_value"):
        if name in attrs:
            value = np.asarray(attrs[name])
            if value.dtype.kind in "fiu" and value.size:
                marks += [float(v) for v in value.ravel() if np.isfinite(v)]
    if not marks:
        return values
    missing = np.isin(values, marks)
    if not missing.any():
        return values
    out = np.array(values, dtype=np.float64)  # a copy: a memory map stays untouched
    out[missing] = np.nan
    return out


def _unpacked(values: np.ndarray, attrs, meta: dict, key: str) -> np.ndarray:
    """Return ``values`` unpacked by their CF ``scale_factor`` / ``add_offset`` attributes.

    netCDF writers (xarray's ``encoding={"dtype": "int16", "scale_factor": ...}``, CF
    packing) store integers that mean ``packed * scale_factor + add_offset``; the packed
    integers were read as the coefficients, 1e4 times too large (round 52 PART b, A55).
    The fill value is matched on the packed integers first (``_missing_as_nan``), as CF
    says. ``meta["cf_packing"]`` records the factors.
    """
    scale = _number_attribute(attrs, "scale_factor")
    offset = _number_attribute(attrs, "add_offset")
    if scale is None and offset is None:
        return values
    scale = 1.0 if scale is None else scale
    offset = 0.0 if offset is None else offset
    meta["cf_packing"] = (f"{key!r} unpacked as stored * scale_factor {scale!r} + add_offset "
                          f"{offset!r} (CF packing)")
    return np.asarray(values, dtype=np.float64) * scale + offset


def _number_attribute(attrs, name: str) -> float | None:
    """Return the finite scalar numeric attribute ``name`` (None when absent); refuse others."""
    if name not in attrs:
        return None
    value = np.asarray(attrs[name])
    if value.dtype.kind not in "fiu" or value.size != 1 or not np.isfinite(value.ravel()[0]):
        raise LogFormatError(f"attribute {name}={attrs[name]!r} is not one finite number "
                             "(CF packing: values = stored * scale_factor + add_offset)")
    return float(value.ravel()[0])


def _lossy_filter(dset, key: str, meta: dict) -> None:
    """Record in ``meta["lossy_storage"]`` that ``dset`` was stored by a lossy HDF5 filter.

    HDF5's scale-offset filter on floating-point data keeps ``scaleoffset`` decimal digits
    (D-scaling): the writer stored each value as whole steps of ``10**-digits`` from its
    chunk's minimum, and the finer digits are not in the file. The values read are then
    neither multiples of the step nor its nearest multiple: they differ from the original
    by up to one step either way (h5py 3, 20,000 x 6 normal values of s.d. 3: -0.99997 to
    +0.99999 steps at 0 digits, -0.996 to +0.989 at 2; the note said "rounded to a whole
    number" / "a multiple of 1e-2", review35). With 0 digits a log of a few tenths of a
    radian read as zeros, without a word (round 52 PART b, A14, A72). The reader cannot
    restore them; it says so.
    """
    digits = dset.scaleoffset
    if digits is None or dset.dtype.kind != "f":
        return
    step = "1" if digits == 0 else f"1e-{digits}"
    meta["lossy_storage"] = (
        f"dataset {key!r} was stored with HDF5's lossy scale-offset filter keeping {digits} "
        f"decimal digit(s): its writer kept every value only to within +-{step} (of the "
        "file's units) and the finer digits are not in the file")


def _refuse_unwritten_rows(dset, path: Path) -> None:
    """Refuse a chunked dataset whose last rows lie in chunks never written.

    A logger that allocates its dataset ahead (``maxshape=(None, M)``, ``shape=(1000, M)``)
    and fills it row by row leaves the chunks past its last row unallocated: HDF5 returns
    the fill value (0) for them. Such a file (still being written, or allocated larger than
    it was filled) was read as a log whose last 400 frames were zero (round 52 PART b, A11).
    Chunks never written hold no data at all, so this tells them apart from real zeros.
    """
    if dset.chunks is None or dset.ndim != 2 or not dset.size:
        return
    rows = dset.chunks[0]
    n_chunks = -(-dset.shape[0] // rows) * -(-dset.shape[1] // dset.chunks[1])
    try:
        if dset.id.get_num_chunks() >= n_chunks:
            return

        def written(row: int) -> bool:  # any chunk of this block of rows stored
            return any(dset.id.get_chunk_info_by_coord((row, col)).byte_offset is not None
                       for col in range(0, dset.shape[1], dset.chunks[1]))

        first_unwritten = -(-dset.shape[0] // rows) * rows  # walk back over the tail
        while first_unwritten > 0 and not written(first_unwritten - rows):
            first_unwritten -= rows
    except (AttributeError, RuntimeError, ValueError, OSError):  # an old libhdf5: cannot tell
        return
    if first_unwritten >= dset.shape[0]:
        return  # chunks missing inside the data, not a tail: sparse writes, read as stored
    raise LogFormatError(
        f"HDF5 file {quoted(path)}: rows {first_unwritten}..{dset.shape[0] - 1} of dataset "
        f"{dset.name!r} ({dset.shape[0]} allocated) were never written: their chunks hold no "
        f"data and read as the fill value {dset.fillvalue!r} (a file still being written, or "
        f"allocated larger than it was filled); copy the written rows to a new file (h5py: "
        f"f[{dset.name!r}][:{first_unwritten}]) and read that")


def _pandas_items(f, key: str, dset) -> list[str] | None:
    """Column names of a pandas ``HDFStore`` fixed-format frame block (``blockN_values``).

    pandas (``DataFrame.to_hdf(format="fixed")``) writes ``KEY/blockN_values`` (frames x
    columns) and the block's column names in ``KEY/blockN_items``; the names were not read
    and the columns taken as Z2, Z3, ... "assumed" (a frame written z11..z2 came out
    reversed, round 52 PART b, A60).
    """
    head, _, tail = key.rpartition("/")
    if not (tail.startswith("block") and tail.endswith("_values")):
        return None
    group = f[head] if head else f
    if _attr_text(group.attrs.get("pandas_type")) != "frame":
        return None
    items = group.get(tail[: -len("_values")] + "_items")
    if items is None or items.ndim != 1 or items.shape[0] != dset.shape[1]:
        return None
    if items.dtype.kind not in "SU":
        return None  # pandas' default column names 0, 1, ...: positions, not modes
    return [v.decode("utf-8", "replace") if isinstance(v, bytes) else str(v) for v in items[()]]


def _time_column(coeffs: np.ndarray, names: list[str], stored: dict, meta: dict,
                 path: Path, key: str) -> tuple[np.ndarray, list[str]]:
    """Take a named time column out of a foreign frame (``time``, ``t_ms``, ``frame``, ...).

    A pandas frame ``df.assign(time=t).to_hdf(...)`` keeps its time column in the same
    block as the modes: it was read as one more mode, Z12 (round 52 PART b, A93). As the
    CSV reader: a frame-number column beside a time (or the file's time dataset) is
    dropped (``meta["frame_column"]``); two time columns, or one beside the file's own
    time dataset, are refused. They were left as modes: a frame of z2..z7, ``time`` and
    ``t_ms`` read as 8 modes named "z2" ... "t_ms", with no rate (review35).
    """
    kinds = [time_kind(name) for name in names]
    timed = [k for k, kind in enumerate(kinds) if kind not in (None, "frame")]
    framed = [k for k, kind in enumerate(kinds) if kind == "frame"]
    if not timed and not framed:
        return coeffs, names
    file_times = "timestamps" in stored or "_frame_numbers" in stored
    for group in (timed, framed):
        axes = [repr(names[k]) for k in group]
        if group is timed and timed and file_times:
            axes.append("the file's time dataset")
        if len(axes) > 1:
            raise LogFormatError(
                f"HDF5 file {quoted(path)}: {key!r} has {len(axes)} time axes "
                f"({', '.join(axes)}); expected one: drop the others (pandas: "
                "df.drop(columns=[...]).to_hdf(NEW, key=KEY, format='fixed')) and read NEW")
    if timed:
        k = timed[0]
        set_timestamps(np.asarray(coeffs[:, k]), kinds[k], stored, meta)
        if kinds[k] != "s":
            meta["time_column"] = f"{names[k]} ({kinds[k]}, converted to s)"
    elif not file_times:
        stored["_frame_numbers"] = np.asarray(coeffs[:, framed[0]])
    if framed and (timed or file_times):
        meta["frame_column"] = f"{names[framed[0]]} (frame numbers, unused: the file has times)"
    drop = timed + framed
    return (np.delete(np.asarray(coeffs), drop, axis=1),
            [name for k, name in enumerate(names) if k not in drop])


def _scale_labels(dset) -> list[str] | None:
    """Return mode names from a string coordinate attached to a foreign column axis.

    netCDF-4 (xarray ``coords={"mode": ["z11", ...]}``) stores the names as a 1-D string
    dataset attached as the dimension scale of axis 1; they were not read and the
    columns taken as Z2, Z3, ... "assumed" (round 52 PART b, A85).
    """
    import h5py

    try:
        dim = dset.dims[1]
        if len(dim) != 1:
            return None
        scale = dim[0]
    except (IndexError, RuntimeError, ValueError, KeyError):
        return None
    if scale.ndim != 1 or scale.shape[0] != dset.shape[1]:
        return None
    if h5py.check_string_dtype(scale.dtype) is None and scale.dtype.kind not in "SU":
        return None
    values = scale[()]
    return [v.decode("utf-8", "replace") if isinstance(v, bytes) else str(v) for v in values]


def _attr_text(value) -> str | None:
    if isinstance(value, np.ndarray) and value.shape == ():
        value = value[()]
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    return value if isinstance(value, str) else None


#: ``pandas_type`` of a pandas ``HDFStore`` table (``format="table"``)
_PANDAS_TABLES = ("frame_table", "series_table", "wide_table", "appendable_frame",
                  "appendable_series")


def _pandas_table_keys(f) -> list[str]:
    """Names of the groups of ``f`` that hold a pandas ``HDFStore`` table."""
    tables: list[str] = []
    f.visititems(lambda name, obj: tables.append(name) if (
        _attr_text(obj.attrs.get("pandas_type")) in _PANDAS_TABLES) else None)
    return tables


def _pandas_data_columns(f, path: Path) -> tuple[np.ndarray, dict] | None:
    """Read a pandas table whose every column is a field named by it, else None.

    ``to_hdf(format="table", data_columns=True)`` writes each column as a field of the
    PyTables compound dataset ``KEY/table``, named by the column: the names are the
    table's own, never pickled, and the values its fields (the ``index`` field is the
    frame index, left as the fixed format's ``axis1`` is). A table whose columns sit in
    a ``values_block_N`` block has its names only in pickled attributes: None, and
    :func:`_refuse_pandas_table` says how to re-save it (round 52 PART b, Left).
    """
    keys = _pandas_table_keys(f)
    if len(keys) != 1:
        return None
    key = keys[0]
    table = f[key].get("table") if hasattr(f[key], "get") else None
    names = getattr(getattr(table, "dtype", None), "names", None)
    if table is None or names is None or table.ndim != 1:
        return None
    fields = [n for n in names if n != "index"]
    text = [n for n in fields if table.dtype[n].shape == () and table.dtype[n].kind in "SUO"]
    if text and all(table.dtype[n].shape == () and table.dtype[n].kind in "fiuSUO"
                    for n in fields):
        # the names are the table's own here, not pickled: the pickle refusal's words
        # ("re-save with format='fixed'") were wrong for a data-columns table with a text
        # column (review36)
        raise LogFormatError(
            f"HDF5 file {quoted(path)}: the pandas table {key!r} holds text column(s) "
            f"{', '.join(repr(n) for n in text)} beside its numbers; modalinfo reads "
            "numeric columns only: drop them before saving (df.drop(columns=[...]).to_hdf"
            "(...)), or save the coefficients alone")
    if not fields or any(table.dtype[n].shape != () or table.dtype[n].kind not in "fiu"
                         for n in fields):
        return None
    rows = table[()]
    meta: dict[str, Any] = {"source_file": path.name, "source_format": "hdf5",
                            "source_dataset": f"{key}/table (a pandas table, data_columns)"}
    stored: dict[str, Any] = {"metadata": meta}
    coeffs = float_columns([rows[n] for n in fields], fields, path)
    if len(fields) > 1:
        coeffs, fields = _time_column(coeffs, fields, stored, meta, path, key)
    stored["modes"], stored["convention"], assumed = mode_columns(fields)
    if assumed:
        stored["_convention_assumed"] = True
    unit = _stated_unit(table.attrs) or _nesting_unit(table, key)[0]
    if unit is not None:
        stored["_unit"] = (unit, f"units attribute of {key!r}")
    _rate_fields(stored, (table.attrs, f"attribute of {key!r},"), (f.attrs, "file attribute"))
    return coeffs, stored


def _refuse_pandas_table(f, path: Path) -> None:
    """Refuse a pandas ``HDFStore`` table (``format="table"``) by name.

    Its frame is a PyTables compound dataset beside PyTables' index arrays; the refusal
    listed those index arrays ("coeffs/_i_table/index/bounds, ...; pick one with --dataset")
    and none of them is the log (round 52 PART b, A02, A03, A06, A10).
    """
    tables = _pandas_table_keys(f)
    if tables:
        key = tables[0]
        raise LogFormatError(
            f"HDF5 file {quoted(path)} holds a pandas HDFStore table (format='table') under "
            f"{key!r} whose column names PyTables keeps only as Python pickles, which "
            "modalinfo never loads; re-save it with pandas: "
            f"pd.read_hdf(PATH, {key!r}).to_hdf(NEW, key={key!r}, format='fixed') (read "
            "with its column names; or format='table', data_columns=True), or "
            ".to_csv(NEW, index=False)")


def _stated_unit(attrs) -> str | None:
    """Return the ``units`` / ``unit`` attribute of a foreign dataset or file (None if absent)."""
    for name in ("units", "unit", "UNITS", "UNIT", "BUNIT"):
        if name in attrs:
            return unit_text(attrs[name])
    return None


def _nesting_unit(dset, key: str) -> tuple[str | None, str]:
    """Return the units attribute of the innermost group nesting ``dset`` (the file's last).

    Returns ``(unit or None, where)``: ``where`` names the group (``key`` for the
    root, as before). Units on the group of ``/run/wfs/coeffs`` were read as "rad
    (assumed)" with a note that the file recorded no units (round 25 PART b, H01).
    """
    group = dset.parent
    while True:
        unit = _stated_unit(group.attrs)
        if unit is not None or group.name == "/":
            return unit, (group.name.strip("/") or key)
        group = group.parent


def _column_names(dset) -> list[str] | None:
    """Column names a foreign dataset gives in an attribute (``labels``, ``modes``, ...)."""
    for key in ("labels", "modes", "columns", "column_names", "mode_names"):
        if key in dset.attrs:
            try:
                items = list(np.asarray(dset.attrs[key]).ravel())
            except (TypeError, ValueError):
                return None
            return [i.decode("utf-8", "replace") if isinstance(i, bytes) else str(i)
                    for i in items]
    return None


def _text_list(value) -> list | None:
    if isinstance(value, bytes | str):
        text = value.decode("utf-8", "replace") if isinstance(value, bytes) else value
        parts = [p for p in text.replace(";", ",").replace(" ", ",").split(",") if p]
        return parts if len(parts) == 2 else None
    try:
        items = list(np.asarray(value).ravel())
    except (TypeError, ValueError):
        return None
    return items if len(items) == 2 else None


def _annotation(dset) -> tuple[str, str] | None:
    """Axis layout a foreign dataset declares: attributes, dimension labels or scales."""
    for key in ("axes", "dims", "dimensions", "axis_names", "dimension_labels", "layout"):
        if key in dset.attrs:
            value = dset.attrs[key]
            if key == "layout":
                text = value.decode() if isinstance(value, bytes) else str(value)
                text = text.strip().lower().replace("-", "_").replace(" ", "_")
                if text in ("frames_first", "time_first", "frames_x_modes", "time_x_modes"):
                    return "frames_first", f"attribute layout={text!r}"
                if text in ("modes_first", "modes_x_frames", "modes_x_time"):
                    return "modes_first", f"attribute layout={text!r}"
                continue
            names = _text_list(value)
            if names is not None:
                names = [n.decode("utf-8", "replace") if isinstance(n, bytes) else str(n)
                         for n in names]
                found = axis_layout(names, f"attribute {key}={names}")
                if found is not None:
                    return found
    try:
        labels = [dim.label for dim in dset.dims]
    except (AttributeError, TypeError, ValueError, RuntimeError):
        return None
    if len(labels) == 2 and all(labels):
        return axis_layout(labels, f"dimension labels {labels}")
    # netCDF-4 names its dimensions by the attached dimension-scale datasets, not by
    # labels: a (mode, time) variable was "looks transposed" (round 31 PART b, a27)
    try:
        scales = [dim[0].name.rsplit("/", 1)[-1] if len(dim) == 1 else None
                  for dim in dset.dims]
    except (AttributeError, TypeError, ValueError, RuntimeError, KeyError, OSError):
        return None
    if len(scales) == 2 and all(scales):
        return axis_layout(scales, f"dimension scales {scales}")
    return None
