"""File-level helpers for every package: paths, the log-format error, atomic writes, sizes.

These are the public homes of what readers and writers everywhere share:
:func:`atomic_write` (a crash leaves the old file or none, never half a file; no
overwrite unless asked), :func:`as_path` and :func:`check_readable` (argument checks
naming the path) and :class:`LogFormatError`. They depend on nothing else of
modalinfo, so any layer may import them.
"""

from __future__ import annotations

import os
import re
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

__all__ = [
    "LogFormatError",
    "as_path",
    "atomic_write",
    "check_readable",
    "format_size",
    "parse_size",
    "writable_free_bytes",
]

#: Size suffixes (lower case) -> bytes: SI (kB = 1000 B) and binary (KiB = 1024 B), with
#: or without the ``B``, as ``dask.utils.parse_bytes`` reads them, so a ``--memory-limit``
#: means the same here as in Dask's own configuration.
_SIZE_UNITS = {"": 1, "b": 1}
for _k, _p in enumerate("kmgtp", start=1):
    _SIZE_UNITS.update({_p: 1000**_k, f"{_p}b": 1000**_k, f"{_p}i": 1024**_k,
                        f"{_p}ib": 1024**_k})
_SIZE = re.compile(r"([0-9]*\.?[0-9]+(?:e[-+]?[0-9]+)?|[0-9]+\.)\s*([a-z]*)")


def parse_size(text: str | float, name: str = "size") -> int:
    """Return a size such as ``"2GB"``, ``"512 MiB"``, ``"2e9"`` or ``1e9`` in bytes.

    Parameters
    ----------
    text : str or float
        A non-negative number with an optional unit: ``B``, ``kB``/``k``, ``MB``,
        ``GB``, ``TB``, ``PB`` (powers of 1000) or ``KiB``/``Ki`` ... ``PiB`` (powers
        of 1024), case-insensitive, as ``dask.utils.parse_bytes`` reads them; a bare
        number is bytes. Needs no optional dependency.
    name : str
        The argument named in the error.

    Returns
    -------
    int
        Bytes (rounded down).

    Raises
    ------
    ValueError
        Naming ``name``, the accepted forms and the value: no number, an unknown
        unit, a negative, infinite or NaN size.
    """
    import math

    if isinstance(text, bool) or not isinstance(text, str | int | float):
        raise ValueError(f"`{name}` must be a size such as '2GB', '512 MiB' or a number of "
                         f"bytes; got {text!r}")
    match = _SIZE.fullmatch(str(text).strip().lower()) if isinstance(text, str) else None
    if isinstance(text, str) and (match is None or match.group(2) not in _SIZE_UNITS):
        raise ValueError(f"`{name}` must be a size such as '2GB', '512 MiB' or a number of "
                         f"bytes (units B, kB, MB, GB, TB, KiB, MiB, GiB, TiB); got {text!r}")
    value = float(match.group(1)) * _SIZE_UNITS[match.group(2)] if match else float(text)
    if not math.isfinite(value) or value < 0:
        raise ValueError(f"`{name}` must be a finite size >= 0; got {text!r}")
    return int(value)


def format_size(n: float) -> str:
    """``n`` bytes in B, KiB, MiB, GiB, TiB with two decimals (``dask.utils.format_bytes``)."""
    for k, prefix in ((4, "Ti"), (3, "Gi"), (2, "Mi"), (1, "ki")):
        if n >= 0.9 * 1024**k:
            return f"{n / 1024**k:.2f} {prefix}B"
    return f"{int(n)} B"


class LogFormatError(ValueError):
    """A file is not a readable log: truncated, corrupted or of an unexpected layout.

    A subclass of ``ValueError``; the message names the file and what is wrong.
    """


def as_path(path: Any, name: str = "path") -> Path:
    """Return ``path`` as a ``Path`` (``TypeError`` for anything but str / PathLike)."""
    if not isinstance(path, str | os.PathLike):
        raise TypeError(f"`{name}` must be a str or os.PathLike; got {type(path).__name__}.")
    return Path(path)


def check_readable(path: Path) -> None:
    """Raise ``FileNotFoundError`` / ``IsADirectoryError`` naming ``path`` if it is no file."""
    if not path.exists():
        raise FileNotFoundError(f"no such file: '{path}'")
    if path.is_dir():
        raise IsADirectoryError(f"'{path}' is a directory, not a log file")


def writable_free_bytes(folder: Path) -> int:
    """Return the free bytes of ``folder``'s file system after a real test write in it.

    A real write (a temporary file, removed at once) answers for permissions, read-only
    mounts and ACLs alike, where ``os.access`` does not. Raises the ``OSError`` of that
    write when the folder cannot take a file.
    """
    import shutil

    with tempfile.TemporaryFile(dir=folder):
        pass
    return shutil.disk_usage(folder).free


def _exists_message(path: Path) -> str:
    return f"'{path}' exists; pass overwrite=True (command line: --overwrite) to replace it"


def _renamed(write: Callable[[Any], None], target: Any, tmp: str, path: Path) -> None:
    """Call ``write(target)``; an error naming the temporary file names ``path`` instead."""
    try:
        write(target)
    except (OSError, ValueError, TypeError) as exc:  # the user knows the target, not the temp
        _rename_in_message(exc, tmp, path)


def _rename_in_message(exc: BaseException, tmp: str, path: Path) -> None:
    """Re-raise ``exc`` with the temporary file's name replaced by the target's."""
    text = str(exc)
    if tmp not in text and Path(tmp).name not in text:
        raise exc
    text = text.replace(tmp, str(path)).replace(Path(tmp).name, path.name)
    try:
        new = type(exc)(text)
    except Exception:  # noqa: BLE001 - an exception type with another signature
        raise exc from None
    raise new from exc


def atomic_write(
    path: Path, write: Callable[[Any], None], *, overwrite: bool, by_name: bool = False
) -> Path:
    """Write a file through ``write`` into a temporary file, then move it in place.

    ``write`` receives a binary file object, or with ``by_name=True`` the temporary
    file's ``Path`` (for libraries such as h5py and astropy that open files by name).
    The temporary file lives in the target directory, so the final rename is atomic:
    a crash leaves either the old file or none, never half a file. Without
    ``overwrite`` an existing target raises ``FileExistsError`` (checked again at the
    final step with a hard link, which cannot clobber).
    """
    path = Path(path)
    if path.is_dir():
        raise IsADirectoryError(f"'{path}' is a directory; give a file name")
    if path.exists() and not overwrite:
        raise FileExistsError(_exists_message(path))
    directory = path.parent
    if not directory.is_dir():
        raise FileNotFoundError(f"directory '{directory}' does not exist (writing '{path}')")
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=directory)
    try:
        if by_name:
            os.close(fd)
            os.unlink(tmp)  # libraries may refuse to write over an existing file
            _renamed(write, Path(tmp), tmp, path)
            with open(tmp, "rb+") as fh:
                os.fsync(fh.fileno())
        else:
            with os.fdopen(fd, "wb") as fh:
                _renamed(write, fh, tmp, path)
                fh.flush()
                os.fsync(fh.fileno())
        os.chmod(tmp, 0o644)
        if overwrite:
            os.replace(tmp, path)
        else:
            try:
                os.link(tmp, path)
            except FileExistsError:
                raise FileExistsError(_exists_message(path)) from None
            except OSError:  # filesystem without hard links
                if path.exists():
                    raise FileExistsError(_exists_message(path)) from None
                os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return path
