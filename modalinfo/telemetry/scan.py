"""Scanning large (memory-mapped) coefficient arrays in row blocks.

A log may be a ``numpy.memmap`` far larger than RAM. These helpers walk it in
blocks of rows and hand the pages of each finished block back to the kernel, so
a pass over a multi-GB file keeps a small resident set. ``ModalLog``,
:func:`~modalinfo.telemetry.summarize` and the writers and checksums of
:mod:`modalinfo.io` share them.
"""

from __future__ import annotations

import mmap
from collections.abc import Iterator

import numpy as np

__all__ = ["SCAN_ELEMENTS", "count_nonfinite", "release_pages", "row_blocks", "scan_rows"]

#: Elements per block when scanning a large array (32 MB of float64).
SCAN_ELEMENTS = 1 << 22


def release_pages(arr: np.ndarray, block: np.ndarray) -> None:
    """Drop the pages of ``block`` (a row block of the read-only memmap ``arr``) from RSS.

    File-backed pages of a memory map count in the process's resident set until the
    kernel evicts them; scanning a multi-GB log would otherwise look like loading it.
    ``MADV_DONTNEED`` is safe for a read-only shared mapping: the next access reads
    the page again from the page cache or the file.
    """
    if not isinstance(arr, np.memmap) or getattr(arr, "mode", None) != "r":
        return
    mm = getattr(arr, "_mmap", None)
    if not isinstance(mm, mmap.mmap) or not hasattr(mmap, "MADV_DONTNEED") or block.size == 0:
        return
    try:
        base = np.frombuffer(mm, dtype=np.uint8).ctypes.data
        start = block.ctypes.data - base
        stop = start + block.nbytes
        page = mmap.PAGESIZE
        start = (start // page) * page
        stop = min(len(mm), -(-stop // page) * page)
        if 0 <= start < stop:
            mm.madvise(mmap.MADV_DONTNEED, start, stop - start)
    except (ValueError, OSError, BufferError):  # pragma: no cover - best effort only
        return


def row_blocks(arr: np.ndarray, rows: int, release: bool = True) -> Iterator[np.ndarray]:
    """Yield ``arr[i:i + rows]`` blocks; release memmap pages after each one."""
    n = arr.shape[0]
    for i0 in range(0, n, rows):
        block = arr[i0 : i0 + rows]
        yield np.asarray(block)
        if release:
            release_pages(arr, block)


def scan_rows(arr: np.ndarray) -> int:
    """Rows per block of a ``(T, M)`` array for a scan of :data:`SCAN_ELEMENTS` elements."""
    return max(1, SCAN_ELEMENTS // max(1, arr.shape[1]))


def count_nonfinite(arr: np.ndarray) -> int:
    """Count NaN/inf values in ``arr``, scanning in blocks (cheap when all finite)."""
    bad = 0
    for block in row_blocks(arr, scan_rows(arr)):
        with np.errstate(over="ignore", invalid="ignore"):
            total = block.sum(dtype=np.float64)
        if np.isfinite(total):
            continue  # a NaN or inf anywhere would make the sum non-finite (or overflow)
        bad += int(block.size - np.count_nonzero(np.isfinite(block)))
    return bad
