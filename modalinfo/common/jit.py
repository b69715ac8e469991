"""The one numba decorator every kernel of modalinfo and closedloop uses.

Kernels are compiled lazily with ``cache=True`` (compiled code is stored beside the
source, so the second Python process does not pay the compile time) and with
``error_model="numpy"`` (division by zero gives inf/nan instead of raising, so the
compiler can vectorise; wrappers validate inputs so that never happens silently) and
``nogil=True`` (a kernel releases the GIL, so callers running estimators from several
threads, which the per-thread work arrays of ``information.kde`` allow, run in parallel).
"""

from __future__ import annotations

import warnings

with warnings.catch_warnings(record=True) as _caught:
    # numba warns (a RuntimeWarning holding a whole traceback, an exception under
    # PYTHONWARNINGS=error) when a NUMBA_* variable does not parse, e.g.
    # NUMBA_NUM_THREADS=abc (adversarial round 9 PART b, rows E15, E17): recorded here
    warnings.simplefilter("always")
    try:
        import numba as nb
    except ValueError as _exc:  # numba checks its NUMBA_* variables at import time
        # e.g. NUMBA_NUM_THREADS=0 (adversarial round 8, row e105): an ImportError that the
        # commands' __main__ report in one line, not numba's traceback
        raise ImportError(f"numba cannot start: {_exc} (check the NUMBA_* environment "
                          "variables, e.g. NUMBA_NUM_THREADS must be >= 1)") from None
for _w in _caught:
    _text = str(_w.message)
    if "could not be parsed" in _text:
        raise ImportError(f"numba cannot start: {_text.splitlines()[0]} (check the NUMBA_* "
                          "environment variables, e.g. NUMBA_NUM_THREADS must be an "
                          "int >= 1)")
    if issubclass(_w.category, EncodingWarning):
        # numba's own open() without an encoding (numba/core/config.py reading
        # /proc/cpuinfo), shown only under -X warn_default_encoding: a note about numba's
        # code, which under -W error::EncodingWarning became a traceback of every command
        # (adversarial round 16 PART b, I10-I12); modalinfo's own files name their encoding
        continue
    warnings.warn_explicit(_w.message, _w.category, _w.filename, _w.lineno)

__all__ = ["jit", "prange"]

#: numba's parallel range, for kernels compiled with ``@jit(parallel=True)``
prange = nb.prange


def jit(*args, **kwargs):
    """Compile with ``numba.njit(cache=True, error_model="numpy", nogil=True)``.

    Used bare (``@jit``) or with extra numba options (``@jit(parallel=True)``).
    """
    options = {"cache": True, "error_model": "numpy", "nogil": True}
    if len(args) == 1 and callable(args[0]) and not kwargs:
        return nb.njit(**options)(args[0])
    options.update(kwargs)
    return nb.njit(*args, **options)
