"""The checksums modalinfo's files carry: the canonical header text and array SHA-256s.

Public because closedloop's result files carry the same checksums as modalinfo's
HDF5 logs (one rule, so a result's logs verify as logs).
"""

from __future__ import annotations

import hashlib
import json

import numpy as np

from modalinfo.telemetry.scan import row_blocks, scan_rows

__all__ = ["dumps", "sha256_of"]


def dumps(header: dict) -> str:
    """One-line ASCII JSON (exact float reprs; non-ASCII escaped)."""
    return json.dumps(header, ensure_ascii=True, allow_nan=False, separators=(",", ":"))


def sha256_of(arr: np.ndarray) -> str:
    """SHA-256 hex digest of ``arr``'s *values* (little-endian, C order), block by block.

    Hashing values rather than raw bytes means a damaged byte-order flag (which
    leaves the bytes intact but changes every value) is caught too.
    """
    digest = hashlib.sha256()
    little = arr.dtype.newbyteorder("<")
    # row blocks as the log's own scans: a memory-mapped log is hashed with a small RSS
    blocks = (arr,) if arr.ndim == 1 else row_blocks(arr, scan_rows(arr))
    for block in blocks:
        digest.update(np.ascontiguousarray(block, dtype=little).data)
    return digest.hexdigest()
