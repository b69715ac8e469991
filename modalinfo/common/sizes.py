"""Sizes in bytes: the one parser and the one formatter of every package.

Part of the ground floor (:mod:`modalinfo.common`). The parser reads what
``dask.utils.parse_bytes`` reads (SI ``kB``, ``MB``, ... = powers of 1000 and binary
``KiB``, ``MiB``, ... = powers of 1024) without importing dask, so ``--memory-limit``
works without the optional ``dist`` extra. The formatter writes **binary units**
(``KiB``... as ``kiB``, ``MiB``, ``GiB``, ``TiB``, two decimals), exactly as
``dask.utils.format_bytes``, so a size a command prints reads the same as Dask's own
memory messages.
"""

from __future__ import annotations

import math
import re

__all__ = ["format_size", "log_bytes", "parse_size"]

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


def log_bytes(log) -> int:
    """Bytes of one float64 copy of ``log``'s coefficients (frames x modes x 8)."""
    return int(log.n_frames) * int(log.n_modes) * 8
