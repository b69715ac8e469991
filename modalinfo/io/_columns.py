"""Names other software gives to mode and time columns (CSV, FITS tables, HDF5, NPZ).

Mode names (case-insensitive unless stated, an optional ``_`` before the index):

============================  ==========  ==========================================
name                          convention  read from the name?
============================  ==========  ==========================================
``Z2``, ``z2``, ``Z_2``       noll        yes (Noll 1976 writes the modes ``Z_j``)
``noll2``, ``noll_2``         noll        yes
``ansi2``, ``osa_2``          ansi        yes
``fringe2``                   fringe      yes
``A2`` / ``F2`` (upper case)  ansi/fringe yes (the labels modalinfo writes)
``a2``, ``a_2`` (lower case)  noll        assumed (Noll's coefficients ``a_j``)
``mode2``, ``mode_2``         noll        assumed (the name gives no convention)
``2`` (a list of indices)     noll        assumed
============================  ==========  ==========================================

Time names: ``time``, ``t``, ``time_s``, ``timestamp(s)``, ``times``, ``time[s]``,
``time (s)`` are seconds; ``time_ms``, ``t_ms``, ``time[ms]``, ``time (ms)`` are
milliseconds, ``time_us`` and ``time_ns`` micro- and nanoseconds (converted to
seconds); ``frame``, ``frames``, ``frame_number``,
``frame_index`` are frame numbers, which become times only with a ``rate``.
"""

from __future__ import annotations

import re

import numpy as np

__all__ = ["mode_columns", "time_kind", "time_arrays", "mode_arrays", "TIME_UNITS"]

#: Seconds per unit of a time column.
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9, "frame": None}

_SECONDS = {"time", "t", "time_s", "t_s", "timestamp", "timestamps", "times", "time[s]",
            "time (s)", "time/s", "timestamp_s"}
_MILLI = {"time_ms", "t_ms", "time[ms]", "time (ms)", "time/ms", "timestamp_ms"}
_MICRO = {"time_us", "t_us", "time[us]", "time (us)", "timestamp_us"}
_NANO = {"time_ns", "t_ns", "time[ns]", "time (ns)", "timestamp_ns"}
_FRAMES = {"frame", "frames", "frame_number", "frame_index", "frame_no", "framenumber"}

# (regex, convention, convention assumed?) tried in order; the first that names every
# column wins. Case-sensitive patterns first (modalinfo's own A<j>/F<j> labels).
_PATTERNS = (
    (re.compile(r"Z_?(\d+)", re.IGNORECASE), "noll", False),
    (re.compile(r"noll_?(\d+)", re.IGNORECASE), "noll", False),
    (re.compile(r"(?:ansi|osa)_?(\d+)", re.IGNORECASE), "ansi", False),
    (re.compile(r"fringe_?(\d+)", re.IGNORECASE), "fringe", False),
    (re.compile(r"A(\d+)"), "ansi", False),
    (re.compile(r"F(\d+)"), "fringe", False),
    (re.compile(r"a_?(\d+)"), "noll", True),
    (re.compile(r"mode_?(\d+)", re.IGNORECASE), "noll", True),
    (re.compile(r"(\d+)"), "noll", True),  # bare indices (an HDF5/NPZ ``modes`` list)
)


def time_kind(name: str) -> str | None:
    """Return ``"s"``, ``"ms"``, ``"us"`` or ``"frame"`` if ``name`` names a time column."""
    key = str(name).strip().lower()
    if key in _SECONDS:
        return "s"
    if key in _MILLI:
        return "ms"
    if key in _MICRO:
        return "us"
    if key in _NANO:
        return "ns"
    if key in _FRAMES:
        return "frame"
    return None


def mode_columns(names: list[str]) -> tuple[list, str, bool]:
    """Return ``(modes, convention, convention_assumed)`` for the column ``names``.

    Names matching none of the patterns (all columns must match the same one) are
    kept as labels (``convention="labels"``, not assumed).
    """
    names = [str(n).strip() for n in names]
    for pattern, convention, assumed in _PATTERNS:
        found = [pattern.fullmatch(n) for n in names]
        if names and all(found):
            modes = [int(f.group(1)) for f in found]
            if len(set(modes)) == len(modes):
                return modes, convention, assumed
    return names, "labels", False


def time_arrays(arrays: dict, stored: dict, meta: dict) -> None:
    """Find the 1-D time array among ``arrays`` (NPZ members, HDF5 datasets).

    ``arrays`` maps names (HDF5 paths allowed) to arrays or datasets with an optional
    ``attrs`` mapping; a ``units`` attribute (``s``/``ms``/``us``) overrides the unit
    implied by the name. Frame numbers go to ``stored["_frame_numbers"]``.
    """
    found = []
    for name, arr in arrays.items():
        kind = time_kind(name.rsplit("/", 1)[-1])
        if kind is None or getattr(arr, "ndim", 0) != 1:
            continue
        unit = _unit_attribute(arr)
        if unit is not None:
            kind = unit
        found.append((0 if kind != "frame" else 1, name, kind, arr))
    if not found:
        return
    found.sort(key=lambda item: item[0])
    _, name, kind, arr = found[0]
    values = np.asarray(arr[()])
    if kind == "frame":
        stored["_frame_numbers"] = values
        return
    stored["timestamps"] = values.astype(np.float64) * TIME_UNITS[kind]
    if kind != "s":
        meta["time_column"] = f"{name} ({kind}, converted to s)"


def _unit_attribute(arr) -> str | None:
    attrs = getattr(arr, "attrs", None)
    if attrs is None:
        return None
    for key in ("units", "unit", "UNITS", "UNIT"):
        if key in attrs:
            value = attrs[key]
            if isinstance(value, np.ndarray) and value.shape == ():
                value = value[()]
            if isinstance(value, bytes):
                value = value.decode("ascii", "replace")
            text = str(value).strip().lower()
            aliases = {"s": "s", "sec": "s", "second": "s", "seconds": "s", "ms": "ms",
                       "millisecond": "ms", "milliseconds": "ms", "us": "us",
                       "microsecond": "us", "microseconds": "us", "ns": "ns",
                       "nanosecond": "ns", "nanoseconds": "ns", "frame": "frame",
                       "frames": "frame"}
            return aliases.get(text)
    return None


def mode_arrays(arrays: dict) -> tuple[list[str], list] | None:
    """Find per-mode 1-D arrays (``z2``, ``z3``, ... one array per mode) among ``arrays``.

    Returns ``(names, arrays)`` sorted by mode index when at least one 1-D numeric
    array that is not a time array has a mode name and all such arrays have mode
    names of one pattern and the same length; otherwise None.
    """
    ones = {
        name: arr for name, arr in arrays.items()
        if getattr(arr, "ndim", 0) == 1 and getattr(arr, "dtype", np.dtype("O")).kind in "fiu"
        and time_kind(name.rsplit("/", 1)[-1]) is None
    }
    if not ones:
        return None
    short = [name.rsplit("/", 1)[-1] for name in ones]
    modes, convention, _ = mode_columns(short)
    if convention == "labels" or len({int(a.shape[0]) for a in ones.values()}) != 1:
        return None
    order = np.argsort(modes, kind="stable")
    names = [list(ones)[k] for k in order]
    return names, [ones[n] for n in names]
