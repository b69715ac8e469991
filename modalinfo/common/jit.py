"""The one numba decorator every kernel of modalinfo and closedloop uses.

Kernels are compiled lazily with ``cache=True`` (compiled code is stored beside the
source, so the second Python process does not pay the compile time) and with
``error_model="numpy"`` (division by zero gives inf/nan instead of raising, so the
compiler can vectorise; wrappers validate inputs so that never happens silently) and
``nogil=True`` (a kernel releases the GIL, so callers running estimators from several
threads, which the per-thread work arrays of ``information.kde`` allow, run in parallel).
"""

from __future__ import annotations

import numba as nb

__all__ = ["jit"]


def jit(*args, **kwargs):
    """Compile with ``numba.njit(cache=True, error_model="numpy", nogil=True)``.

    Used bare (``@jit``) or with extra numba options (``@jit(parallel=True)``).
    """
    options = {"cache": True, "error_model": "numpy", "nogil": True}
    if len(args) == 1 and callable(args[0]) and not kwargs:
        return nb.njit(**options)(args[0])
    options.update(kwargs)
    return nb.njit(*args, **options)
