"""What made an output: the package version, the command line, the input's hash and size.

Part of the ground floor (:mod:`modalinfo.common`). forecast.json, ``reorder --out``'s
JSON and the logs ``convert`` writes recorded their settings but not the code, the
command nor the input that produced them (adversarial round 18 PART b, rows P01-P06);
batch rows and closedloop results recorded theirs each its own way. :func:`provenance`
is the one small record every such output carries.

No time of day and no absolute path is recorded: the same command on the same input
with the same code gives the same record, so the outputs that were byte-identical on a
re-run (forecast.json, reorder's JSON, a converted log; rounds 14 and 18) stay so. The
input is named by its SHA-256 and size, not by where it lay; the command line is as
typed (a path in it is the user's own word for the file).
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = ["file_fingerprint", "png_metadata", "provenance", "sha256_file"]

_HASH_CHUNK = 1 << 20


def sha256_file(path: str | os.PathLike) -> str:
    """SHA-256 of a file's bytes, read in 1 MiB chunks (a FIFO or device refused first).

    Parameters
    ----------
    path : str or os.PathLike
        A regular file.

    Returns
    -------
    str
        64 lower-case hex digits, as ``hashlib.sha256(data).hexdigest()``.
    """
    from modalinfo.common.files import check_readable

    check_readable(Path(path))  # `batch fifo.npz` blocked here forever
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        while block := fh.read(_HASH_CHUNK):
            digest.update(block)
    return digest.hexdigest()


def file_fingerprint(path: str | os.PathLike) -> dict[str, Any]:
    """Return ``{"sha256": <hex>, "bytes": <size>}`` of a file's content.

    Parameters
    ----------
    path : str or os.PathLike
        A regular file.

    Returns
    -------
    dict
        Its SHA-256 (hex) and its size [bytes].
    """
    return {"sha256": sha256_file(path), "bytes": os.stat(path).st_size}


def provenance(argv: Sequence[str] | None, *, source: str | os.PathLike | None = None,
               seed: int | None = None) -> dict[str, Any]:
    """Return the provenance record of an output.

    Parameters
    ----------
    argv : sequence of str or None
        The command line as typed, the program first (``["modalinfo", "forecast",
        "night.npz", "--out", "f/"]``); None for a call from Python (recorded as null).
    source : str or os.PathLike, optional
        The input file: its SHA-256 and size are recorded (:func:`file_fingerprint`).
    seed : int, optional
        The random seed, where the command takes one.

    Returns
    -------
    dict
        ``{"modalinfo": version, "command": [...] or None, "input": {"sha256", "bytes"}
        or None, "seed": int or None}``; ``version`` is
        ``modalinfo.common.tasks.keys.package_version()`` (the version number and the
        source fingerprint, as in batch rows). JSON-ready, with no time of day.
    """
    from modalinfo.common.tasks.keys import package_version

    return {
        "modalinfo": package_version(),
        "command": None if argv is None else [str(a) for a in argv],
        "input": None if source is None else file_fingerprint(source),
        "seed": None if seed is None else int(seed),
    }


def png_metadata(record: dict[str, Any] | None) -> dict[str, str] | None:
    """Return matplotlib's PNG ``metadata=`` carrying ``record`` (None: no metadata).

    The record goes as compact JSON with sorted keys in the PNG's ``Description`` text
    chunk, so a figure separated from its folder still names the code, command and
    input that made it (adversarial round 27 PART b, P09: forecast's PNGs; P20:
    batch's archive plots). Readers: ``PIL.Image.open(path).text["Description"]``.

    Parameters
    ----------
    record : dict or None
        A JSON-ready record, e.g. :func:`provenance`'s.

    Returns
    -------
    dict or None
        ``{"Description": <json>}`` for ``Figure.savefig(..., metadata=...)``.
    """
    import json

    if record is None:
        return None
    return {"Description": json.dumps(record, sort_keys=True, separators=(",", ":"))}
