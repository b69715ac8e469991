"""Cache of DM-space K-L builds (``dm_kl_modes``), in the process and optionally on disk.

A K-L build costs ``~n_valid^3`` (3 s of CPU at 1,584 actuators, ~50 s at 4,600;
``benchmarks/RESULTS.md``, "4-m loop"), and a sweep, a comparison or a second run of the
same mirror asks for the same modes again. The result depends only on the key below:
the pupil's mask and diameter, the actuator grid (count, pitch, coupling, truncation,
illumination threshold), ``r0``, ``L0``, the number of modes and ``tip_tilt_apart``.

- **In the process**: the last :data:`MEMORY_ENTRIES` builds, keyed by that key; a hit
  returns copies (the caller may write into its arrays).
- **On disk**, only when the environment variable :data:`CACHE_ENV`
  (``MODALINFO_DM_KL_CACHE``) names a directory: one ``dmkl-<sha256 of the key>.npz`` per
  build holding ``m2c``, ``variances``, the key's text and the SHA-256 of the two arrays'
  bytes. A file is used only if its key text equals the request's and the checksum
  matches; otherwise (corrupt, truncated, another version) the modes are rebuilt and the
  file is replaced. Files are written atomically (``modalinfo.common.files.atomic_write``).
  Delete the directory to clear it.

:data:`VERSION` is part of the key: a change of the algorithm that changes its numbers
bumps it, so old files are never read back.
"""

from __future__ import annotations

import hashlib
import io
import os
import threading
from collections import OrderedDict
from collections.abc import Callable
from pathlib import Path

import numpy as np

from modalinfo.common.files import quoted
from modalinfo.common.quiet import warn

__all__ = ["CACHE_ENV", "MEMORY_ENTRIES", "VERSION", "cached_build", "build_key", "clear"]

#: environment variable naming the on-disk cache directory (unset: no disk cache)
CACHE_ENV = "MODALINFO_DM_KL_CACHE"
#: builds kept in the process (each ~n_valid x n_modes x 8 bytes: 19 MB at 1,584 x 1,500,
#: 54 MB for est-mcao's five mirrors): more than a model's mirrors, so that a second model
#: of the same configuration (a second run, the error budget's probe) finds all of them
#: (with 4, est-mcao's five evicted one another: every build was repeated)
MEMORY_ENTRIES = 8
#: version of the build's numbers (part of the key)
VERSION = 4

_memory: OrderedDict[str, tuple[np.ndarray, np.ndarray]] = OrderedDict()
#: guards _memory: a hit's move_to_end after another thread evicted the key raised KeyError
_LOCK = threading.Lock()


def build_key(influence, r0: float, outer_scale: float, n_keep: int,
              tip_tilt_apart: bool) -> str:
    """Text that identifies a build: every input of ``dm_kl_modes`` (floats exactly)."""
    mask = np.ascontiguousarray(np.asarray(influence.pupil.mask, dtype=bool))
    mask_hash = hashlib.sha256(np.packbits(mask).tobytes()).hexdigest()
    parts = (f"v={VERSION}", f"mask={mask.shape}:{mask_hash}",
             f"diameter={float(influence.pupil.diameter)!r}",
             f"n_actuators={influence.n_actuators}", f"pitch={float(influence.pitch)!r}",
             f"coupling={float(influence.coupling)!r}",
             f"truncation={float(influence.truncation)!r}",
             f"threshold={float(influence.threshold)!r}", f"r0={float(r0)!r}",
             f"outer_scale={float(outer_scale)!r}", f"n_keep={int(n_keep)}",
             f"tip_tilt_apart={bool(tip_tilt_apart)}")
    return ";".join(parts)


def _checksum(m2c: np.ndarray, var: np.ndarray) -> str:
    h = hashlib.sha256()
    for a in (m2c, var):
        h.update(repr(a.shape).encode())
        h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
    return h.hexdigest()


def _disk_path(key: str) -> Path | None:
    folder = os.environ.get(CACHE_ENV)
    if not folder:
        return None
    return Path(folder) / f"dmkl-{hashlib.sha256(key.encode()).hexdigest()}.npz"


def _read(path: Path, key: str) -> tuple[np.ndarray, np.ndarray] | None:
    """Return the arrays of a valid cache file for ``key``, else None (missing, not valid)."""
    if not path.is_file():
        return None
    try:
        # the file opened here, closed here: np.load(path) raising inside NpzFile on a
        # truncated file left it open (ResourceWarning; round 45 PART a, K05)
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as f:
            m2c, var = np.array(f["m2c"]), np.array(f["variances"])
            stored_key, checksum = str(f["key"]), str(f["checksum"])
    except Exception:  # noqa: BLE001 - any unreadable file is rebuilt
        return None
    if (stored_key != key or checksum != _checksum(m2c, var) or m2c.dtype != np.float64
            or var.dtype != np.float64):
        return None
    return m2c, var


def _write(path: Path, key: str, m2c: np.ndarray, var: np.ndarray) -> None:
    from modalinfo.common.files import atomic_write

    def write(fh) -> None:
        buf = io.BytesIO()
        np.savez(buf, m2c=m2c, variances=var, key=np.array(key),
                 checksum=np.array(_checksum(m2c, var)))
        fh.write(buf.getvalue())

    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write(path, write, overwrite=True)
    except OSError as exc:  # a cache that cannot be written only costs the rebuild
        warn(f"the DM-space K-L cache could not write {quoted(path)} ({exc}); "
             f"set {CACHE_ENV} to a writable directory or unset it.",
             RuntimeWarning, stacklevel=4)


def cached_build(key: str, build: Callable[[], tuple[np.ndarray, np.ndarray]]
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Return ``build()``'s ``(m2c, variances)`` for ``key``, from a cache when there.

    Copies are returned (never the cached arrays themselves).
    """
    with _LOCK:
        hit = _memory.get(key)
        if hit is not None:
            _memory.move_to_end(key)
    if hit is None:
        path = _disk_path(key)
        hit = None if path is None else _read(path, key)
        if hit is None:
            hit = build()
            if path is not None:
                _write(path, key, hit[0], hit[1])
        for a in hit:
            a.flags.writeable = False
        with _LOCK:
            _memory[key] = hit
            while len(_memory) > MEMORY_ENTRIES:
                _memory.popitem(last=False)
    return hit[0].copy(), hit[1].copy()


def clear() -> None:
    """Forget the builds kept in the process (the disk cache is left as it is)."""
    _memory.clear()
