"""``ModalLog``: a time series of modal (Zernike, K-L, ...) coefficients with its context.

A log holds coefficients ``(T, M)`` (time is axis 0), its time axis (a sample rate
or explicit timestamps, in seconds), the mode of every column, the indexing
convention, the units and free-form metadata. It is immutable in practice: every
operation returns a new log and the coefficient array is exposed read-only. It is a
view of the array given, not a copy (a log of a memory-mapped file stays one): writing that
array afterwards changes the log, so give a copy of a buffer you will reuse (adversarial
round 9, row l-input-mutated-after).

Decisions documented here (see also ``docs/ARCHITECTURE.md``):

* ``modes`` default: the first ``M`` modes after piston, i.e. Noll / Fringe
  ``2 .. M + 1`` and ANSI ``1 .. M`` (tip first), which is what WFS loops log.
  ``convention="labels"`` (non-Zernike modes such as ``"KL1"``) requires ``modes``.
* ``labels``: ``"Z<j>"`` for Noll, ``"A<j>"`` for ANSI/OSA (j from 0 = piston),
  ``"F<j>"`` for Fringe (j from 1 = piston); the strings themselves for ``"labels"``.
* Every Zernike convention here is unit-RMS normalised (Noll 1976) with the same
  functions ``sqrt(n+1) R_n^|m| {cos, sin}(|m| theta)``: ANSI/OSA's ``Z_n^m`` with
  ``m < 0`` for sine is the same function as Noll's odd-j sine term (no sign flip),
  so converting conventions only renames and reorders columns. Classical Fringe
  polynomials are *peak* normalised; convert such coefficients with
  :func:`modalinfo.telemetry.units.rms_from_peak_normalized` before building a log.
* Time axis: ``rate`` (Hz) gives ``times = start_time + arange(T) / rate``;
  ``timestamps`` (s, strictly increasing) are used as given. With both, the median
  sample interval must equal ``1 / rate`` to a relative 1e-3. With neither,
  ``rate``, ``times`` and ``duration`` are ``None`` and time selection is refused.
* ``duration = n_frames / rate`` (the span the samples cover).
* 1-D ``coeffs`` is an error (use ``x[:, None]`` for one mode); integer input is
  converted to float64; float32 and float64 are kept, a ``numpy.memmap`` stays one.
* Non-finite values: ``nonfinite="raise"`` (default) refuses them; ``"drop"`` removes
  the frames holding any; ``"interpolate"`` fills each mode linearly in time (constant
  beyond the ends). A repair is recorded in ``log.repairs`` and appended to
  ``metadata["repairs"]``, never silent and never a warning.
"""

from __future__ import annotations

import contextlib
import contextvars
import copy
import math
import numbers
import re
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np

from modalinfo.common.records import same_value
from modalinfo.common.validation import (
    RATE_RANGE,
    check_choice,
    check_int,
    check_rate,
    check_real,
    warn_unusual_rate,
)
from modalinfo.telemetry.checks import (
    CONVENTIONS,
    NONFINITE_POLICIES,
    PISTON_TIPTILT,
    TIME_RESOLUTION,
    as_coeffs,
    check_metadata,
    check_modes,
    check_timestamps,
    coarse_start_spacing,
    find_label,
    label_key,
    mode_labels,
    mode_span,
    transposed_shape,
)
from modalinfo.telemetry.scan import count_nonfinite, row_blocks
from modalinfo.telemetry.units import check_units, check_wavelength, unit_scale

__all__ = ["ModalLog"]

_RATE_RTOL = 1e-3
#: True while ``modalinfo.io`` reads a file modalinfo wrote (``stored_times``)
_STORED_TIMES: contextvars.ContextVar[bool] = contextvars.ContextVar("_STORED_TIMES",
                                                                     default=False)


def assumed_fields(metadata: dict | None) -> tuple[list[str], str]:
    """Return what a log's reader assumed: ``(keys, "units rad, modes Z2..Z51 (noll)")``.

    ``metadata["assumed"]`` (set by ``modalinfo.io.load`` for what the file does not
    record and no hint gave), in the order units, convention, modes; the convention is
    left out when the modes are named (their text names it). ``([], "")`` when nothing
    was assumed. The one wording of the commands' note and of ``batch``'s ``assumed``
    column (round 41 PART b, B02).
    """
    assumed = (metadata or {}).get("assumed")
    if not isinstance(assumed, dict) or not assumed:
        return [], ""
    keys = [k for k in ("units", "convention", "modes") if k in assumed]
    if "modes" in keys and "convention" in keys:
        keys.remove("convention")
    return keys, ", ".join(f"{k} {assumed[k]}" for k in keys)


@contextlib.contextmanager
def stored_times() -> Iterator[None]:
    """Build logs without the warning on the rate their timestamps imply.

    For the readers of modalinfo's own files: their frame times were checked when the
    log was written, and are read as stored (as a stored rate is: Leftovers 23-plaus,
    26-rate), not warned on every read. A context variable, so other threads still warn.
    """
    token = _STORED_TIMES.set(True)
    try:
        yield
    finally:
        _STORED_TIMES.reset(token)


def _warn_timestamps_rate(t: np.ndarray) -> None:
    """Warn, as ``rate=`` is warned, on the rate of frame times ``t`` [s] by their median.

    Adversarial round 25 P13 / P15 / P16: times 1000 s apart (a clock in ms read as
    seconds) gave a 0.001 Hz log silently where ``rate=0.001`` warned. The median
    interval, not the mean: a gapped night at 1 kHz has a mean rate below 1 Hz. No
    warning where the log's (mean) rate is outside ``RATE_RANGE``: the analyses and
    the commands refuse that log (``validation.log_rate_problem``), and the refusal
    alone is said.
    """
    if t.shape[0] < 2 or _STORED_TIMES.get():
        return
    mean_rate = (t.shape[0] - 1) / float(t[-1] - t[0])
    if not RATE_RANGE[0] <= mean_rate <= RATE_RANGE[1]:
        return
    interval = float(np.median(np.diff(t)))
    warn_unusual_rate(1.0 / interval, "timestamps", interval=interval)
#: largest float64 spacing of the times ``start_time + k / rate`` allowed, as a fraction
#: of the frame interval: the rule of explicit timestamps (checks.TIME_RESOLUTION)
_TIME_RESOLUTION = TIME_RESOLUTION


def _check_frame_columns(coeffs, labels: list[str]) -> None:
    """Refuse a DataFrame whose column names are not the labels the log would give.

    ``ModalLog(df)`` with columns ``Z5, Z6, Z7`` and no ``modes`` was labelled Z2, Z3,
    Z4 (the default Noll modes) without a word, the names the scientist gave dropped
    (round 12 PART a, row log-from-df-named). A DataFrame with default integer column
    names (0, 1, ...) or with exactly the default labels is accepted.
    """
    columns = getattr(coeffs, "columns", None)
    if columns is None or getattr(coeffs, "ndim", None) != 2:
        return
    names = [str(c) for c in columns]
    if names in ([str(k) for k in range(len(names))], labels):
        return
    shown = ", ".join(names[:4]) + (", ..." if len(names) > 4 else "")
    raise ValueError(
        f"`coeffs` is a DataFrame with named columns ({shown}) but no `modes` was given: "
        f"they would be labelled {', '.join(labels[:4])}{', ...' if len(labels) > 4 else ''}"
        " by default; give the modes (e.g. modes=[5, 6, 7] for Z5, Z6, Z7, or "
        "modes=list(df.columns), convention='labels').")


def _column_modes(names: list, convention: str) -> list | None:
    """Return the modes a DataFrame's column names state, or None when they name none.

    Integers (not the default 0, 1, ...) are indices in ``convention``; strings are
    read as the convention's labels (``Z4`` Noll, ``A4`` ANSI, ``F4`` Fringe); with
    ``convention="labels"`` the names are labels. Other names (``tip``, ``focus``) state
    no mode: ``modes`` names those columns.
    """
    if all(isinstance(n, int | np.integer) and not isinstance(n, bool | np.bool_)
           for n in names):
        ints = [int(n) for n in names]
        return None if ints == list(range(len(ints))) else ints
    if not all(isinstance(n, str) for n in names):
        return None
    if convention == "labels":
        return [label_key(n) for n in names]
    prefix = mode_labels([0], convention)[0][:-1]
    found = [re.fullmatch(rf"{re.escape(prefix)}(\d+)", n.strip()) for n in names]
    return [int(m.group(1)) for m in found] if all(found) else None


def _check_named_columns(coeffs, mode_list: list, convention: str) -> None:
    """Refuse ``modes`` that contradict the modes a DataFrame's column names state.

    ``ModalLog(df, modes=[2, ..., 7])`` with columns ``Z4, Z2, Z3, Z7, Z5, Z6`` labelled
    the ``Z4`` column Z2 without a word (adversarial round 42 PART a, M03, M04, M20):
    the names were read only when ``modes`` was missing. A column name that states no
    mode (``tip``) is named by ``modes``; with ``convention="labels"`` only a reordering
    of the same labels is refused (other names are the user's renaming).
    """
    columns = getattr(coeffs, "columns", None)
    if columns is None or getattr(coeffs, "ndim", None) != 2:
        return
    names = list(columns)
    stated = _column_modes(names, convention)
    if stated is None or len(stated) != len(mode_list):
        return
    given = ([label_key(str(m)) for m in mode_list] if convention == "labels"
             else [int(m) for m in mode_list])
    if stated == given:
        return
    if convention == "labels" and sorted(map(str, stated)) != sorted(map(str, given)):
        return

    def show(items):
        return ", ".join(str(i) for i in items[:4]) + (", ..." if len(items) > 4 else "")

    raise ValueError(
        f"`coeffs` is a DataFrame whose columns are named ({show(names)}) but `modes` "
        f"labels them ({show(mode_labels(mode_list, convention))}): the names and "
        "`modes` disagree; reorder the columns to match `modes`, give `modes` in the "
        "columns' order, or pass df.to_numpy() if the names are wrong.")


def _check_time_index(coeffs, rate: float | None) -> None:
    """Refuse a DataFrame whose DatetimeIndex / TimedeltaIndex contradicts the log.

    The index was dropped: rows shuffled or reversed in time by their index were read
    in that order, and ``rate=500`` kept beside a 1 ms index (adversarial round 42 PART
    a, M08-M10), where ``rate`` and ``timestamps`` that disagree are refused. The
    index's times are not adopted (``rate`` or ``timestamps`` give the time axis, as
    before); they must be strictly increasing and, with ``rate``, agree with it.
    """
    index = getattr(coeffs, "index", None)
    if getattr(coeffs, "ndim", None) != 2 or type(index).__name__ not in (
            "DatetimeIndex", "TimedeltaIndex") or len(index) < 2:
        return
    offsets = index - index[0]
    seconds = np.asarray(offsets.total_seconds(), dtype=np.float64)
    steps = np.diff(seconds)
    if not np.all(steps > 0.0):  # NaN (NaT) too
        k = int(np.flatnonzero(~(steps > 0.0))[0])
        raise ValueError(
            f"`coeffs` is a DataFrame whose {type(index).__name__} is not strictly "
            f"increasing (row {k + 1}: {index[k + 1]} after {index[k]}): its rows are not "
            "in time order; sort them (df.sort_index()) and drop repeated or missing "
            "times, or pass df.to_numpy() if the index is not the frames' time.")
    if rate is not None:
        from modalinfo.telemetry.sampling import rate_agrees

        if not rate_agrees(seconds, rate, _RATE_RTOL):
            median_dt = float(np.median(steps))
            raise ValueError(
                f"`rate` ({rate} Hz) disagrees with the {type(index).__name__} of `coeffs` "
                f"(median interval {median_dt:.6g} s, i.e. {1.0 / median_dt:.6g} Hz); "
                "give the rate of the index, or pass df.to_numpy() if the index is not "
                "the frames' time.")


def _count(value) -> int | None:
    """``len(value)`` of a sequence or 1-D array, else None (refused later, by its rule)."""
    if value is None or isinstance(value, str | bytes):
        return None
    try:
        return len(value) if np.ndim(value) == 1 else None
    except Exception:  # noqa: BLE001 - a closed h5py dataset raises RuntimeError: its
        return None  # own check names the argument (as_ndarray, round 19)


def _check_layout(coeffs, shape: tuple[int, int], modes, timestamps) -> None:
    """Refuse ``coeffs`` that look stored modes x frames, by the file readers' rule.

    ``ModalLog(x)`` of a (50 modes, 400 frames) array was read as 50 frames of 400
    modes without a word, where the readers refuse the same shape (round 23 PART a,
    m1). The evidence is the readers' (:func:`modalinfo.telemetry.checks.transposed_shape`,
    ``modes`` or ``timestamps`` with one entry per row); what confirms the layout is
    theirs too: ``modes`` with one entry per column, ``timestamps`` with one per row, or
    a DataFrame's column names. So a short log of thousands of named modes is accepted.
    """
    n_rows, n_cols = shape
    fix = (f"logs are (T frames, M modes): pass coeffs.T to read {n_cols} frames of "
           f"{n_rows} modes")
    n_modes, n_times = _count(modes), _count(timestamps)
    if n_rows != n_cols and (n_modes == n_rows or n_times == n_cols):
        which = (f"`modes` names {n_rows} modes, one per row" if n_modes == n_rows else
                 f"`timestamps` has {n_cols} times, one per column")
        raise ValueError(f"`coeffs` of shape {shape} looks transposed (modes x frames): "
                         f"{which}; {fix}.")
    if modes is not None or timestamps is not None:
        return
    columns = getattr(coeffs, "columns", None)
    if columns is not None and [str(c) for c in columns] != [str(k) for k in range(n_cols)]:
        return  # named columns (checked against the labels by _check_frame_columns)
    why = transposed_shape(n_rows, n_cols)
    if why is not None:
        raise ValueError(
            f"`coeffs` of shape {shape} looks transposed (modes x frames): {why}; {fix}, "
            f"or confirm {n_rows} frames of {n_cols} modes by naming the columns (modes=, "
            "one per column) or timing the rows (timestamps=, one per row).")


class ModalLog:
    """A telemetry log of modal coefficients ``(T, M)`` with time axis, modes and units.

    Parameters
    ----------
    coeffs : array_like, shape (T, M)
        Coefficients, time along axis 0. float32 and float64 are kept as given (not
        copied; a ``numpy.memmap`` stays memory-mapped); integers become float64. An
        array that looks stored modes x frames is refused as the file readers refuse
        it: more than 5000 columns and more columns than rows, or more than 64 columns
        and at least 4 times as many as rows, with neither ``modes`` nor
        ``timestamps`` (nor a DataFrame's column names) to confirm the layout; so are
        ``modes`` with one entry per row and ``timestamps`` with one per column.
    rate : float, optional
        Sample rate in Hz, within 1 mHz - 1 MHz (the rule of the command lines'
        ``--rate``). Frames are at ``start_time + arange(T) / rate`` seconds unless
        ``timestamps`` are given. A rate below 1 Hz or above 100 kHz (no wavefront
        sensor runs there) is kept with a ``UserWarning``: ``rate=0.001`` is usually
        the period of a 1 kHz loop (an archive of averaged coefficients is the
        exception the warning allows).
    timestamps : array_like, shape (T,), optional
        Frame times in seconds, strictly increasing. If ``rate`` is also given, the
        median interval must equal ``1 / rate`` to a relative ``1e-3``.
    modes : sequence of int or str, length M, optional
        Mode of each column: indices in ``convention`` (ints) or str labels when
        ``convention="labels"``. Default: the ``M`` modes after piston (Noll/Fringe
        ``2..M+1``, ANSI ``1..M``).
    convention : {"noll", "ansi", "fringe", "labels"}
        Indexing of ``modes``. All Zernike conventions are unit-RMS normalised.
    units : {"rad", "nm", "um", "waves"}
        Units of ``coeffs`` (phase in rad or waves, or OPD in nm or um).
    wavelength : float, optional
        Wavelength in metres at which phase is defined (needed to convert between
        phase and OPD units). Must be in ``[1e-7, 1e-4]`` m (100 nm - 100 um).
    metadata : dict, optional
        Free-form JSON-serialisable information (e.g. ``telescope``, ``date``,
        ``loop`` = ``"open"``/``"closed"``, ``source``). Stored as a copy.
    nonfinite : {"raise", "drop", "interpolate"}
        Policy for NaN/inf coefficients (see the module docstring).
    start_time : float
        Time of the first frame in seconds when the time axis comes from ``rate``
        (ignored with ``timestamps``). Default 0.

    Attributes
    ----------
    coeffs : numpy.ndarray, shape (T, M)
        Read-only coefficient array (may be a ``numpy.memmap``).
    repairs : tuple of str
        Repairs made while building this log (empty unless ``nonfinite`` acted).

    Raises
    ------
    TypeError
        Non-numeric or complex ``coeffs``, non-int modes for a Zernike convention,
        non-dict or non-JSON ``metadata``.
    ValueError
        Wrong dimensions, a layout that looks transposed, empty log, unknown units or
        convention, ``modes`` not matching the columns, non-monotonic timestamps,
        ``rate`` outside 1 mHz - 1 MHz or disagreeing with ``timestamps``, or non-finite
        values with ``nonfinite="raise"``.

    Warns
    -----
    UserWarning
        ``rate`` below 1 Hz or above 100 kHz (see ``rate``).
    """

    __slots__ = (
        "_coeffs",
        "_rate",
        "_timestamps",
        "_start_time",
        "_modes",
        "_convention",
        "_units",
        "_wavelength",
        "_metadata",
        "_repairs",
        # data_fingerprint of a log whose bytes nobody can write (a read-only memory map),
        # so that apply_outlier_policy does not read the file again (issue 27)
        "_fingerprint",
    )

    def __init__(
        self,
        coeffs,
        *,
        rate: float | None = None,
        timestamps=None,
        modes: Sequence[int] | Sequence[str] | None = None,
        convention: str = "noll",
        units: str = "rad",
        wavelength: float | None = None,
        metadata: dict | None = None,
        nonfinite: str = "raise",
        start_time: float = 0.0,
    ) -> None:
        if isinstance(coeffs, ModalLog):
            raise TypeError("`coeffs` must be an array (T, M); got a ModalLog (use log.coeffs).")
        arr = as_coeffs(coeffs)
        n_frames, n_modes = arr.shape
        if not isinstance(convention, str):
            raise TypeError(f"`convention` must be a str; got {convention!r}.")
        convention = check_choice(convention.lower(), "convention", CONVENTIONS)
        units = check_units(units)
        check_choice(nonfinite, "nonfinite", NONFINITE_POLICIES)
        if rate is not None:
            rate = check_rate(rate)
        if wavelength is not None:
            wavelength = check_wavelength(wavelength)
        start_time = check_real(start_time, "start_time")
        _check_layout(coeffs, arr.shape, modes, timestamps)
        _check_time_index(coeffs, rate if timestamps is None else None)
        t = None if timestamps is None else check_timestamps(timestamps, n_frames)
        if t is None and rate is not None and n_frames > 1:
            # float64 must tell the frames apart: a start in ns since 1970 (1.7e18) or
            # 1e17 s gave every frame the same time (adversarial round 9, row l-start-huge)
            ulp = coarse_start_spacing(start_time, n_frames, rate)
            if ulp is not None:
                raise ValueError(
                    f"`start_time` ({start_time} s) is too large for the frame interval "
                    f"(1 / rate = {1.0 / rate:.3g} s): float64 times near it are {ulp:.3g} s "
                    f"apart, more than {_TIME_RESOLUTION:.0%} of an interval; give the start "
                    "in seconds relative to a nearer origin (and keep the origin in "
                    "metadata)."
                )
        if t is not None and rate is not None and n_frames > 1:
            from modalinfo.telemetry.sampling import rate_agrees

            # the median or the mean regular interval: the median alone was 0.2 % off
            # under 5 % timing noise and 2.4 % off for float32 times (audit 10-time)
            if not rate_agrees(t, rate, _RATE_RTOL):
                median_dt = float(np.median(np.diff(t)))
                raise ValueError(
                    f"`rate` ({rate} Hz) disagrees with `timestamps` (median interval "
                    f"{median_dt:.6g} s, i.e. {1.0 / median_dt:.6g} Hz); give one or make them "
                    "agree."
                )
        mode_list = check_modes(modes, convention, n_modes)
        if modes is None:
            _check_frame_columns(coeffs, mode_labels(mode_list, convention))
        else:
            _check_named_columns(coeffs, mode_list, convention)
        meta = check_metadata(metadata)

        repairs: list[str] = []
        n_bad = count_nonfinite(arr)
        if n_bad:
            finite = np.isfinite(arr)
            bad_rows = np.flatnonzero(~finite.all(axis=1))
            if nonfinite == "raise":
                i = int(bad_rows[0])
                j = int(np.flatnonzero(~finite[i])[0])
                raise ValueError(
                    f"`coeffs` must be finite; got {n_bad} NaN or infinite value(s) in "
                    f"{bad_rows.size} frame(s), first at frame {i}, column {j} "
                    f"(pass nonfinite='drop' or 'interpolate' to repair)."
                )
            if nonfinite == "drop":
                keep = np.ones(n_frames, dtype=bool)
                keep[bad_rows] = False
                if not keep.any():
                    raise ValueError(
                        "`coeffs` has a non-finite value in every frame; nonfinite='drop' "
                        "would leave an empty log."
                    )
                if t is None and rate is not None:
                    t = start_time + np.arange(n_frames, dtype=np.float64) / rate
                arr = np.ascontiguousarray(arr[keep])
                arr.flags.writeable = False
                if t is not None:
                    t = t[keep]
                    t.flags.writeable = False
                repairs.append(
                    f"nonfinite='drop': dropped {bad_rows.size} frame(s) holding "
                    f"{n_bad} non-finite value(s)"
                )
            else:  # interpolate
                if t is not None:
                    x = t
                elif rate is not None:
                    x = start_time + np.arange(n_frames, dtype=np.float64) / rate
                else:
                    x = np.arange(n_frames, dtype=np.float64)
                out = np.array(arr, copy=True, order="C")
                n_held = 0
                for j in np.flatnonzero(~finite.all(axis=0)):
                    good = finite[:, j]
                    if not good.any():
                        raise ValueError(
                            f"`coeffs` column {j} (mode {mode_list[j]!r}) has no finite value; "
                            "nonfinite='interpolate' cannot fill it."
                        )
                    kept = np.flatnonzero(good)
                    n_held += int(kept[0]) + (n_frames - 1 - int(kept[-1]))
                    out[~good, j] = np.interp(x[~good], x[good], out[good, j])
                out.flags.writeable = False
                arr = out
                # values before a column's first or after its last finite value are not
                # interpolated but held constant: a mode missing for a whole night was
                # filled with one number and reported as interpolated (round 18, l10)
                held = (f", {n_held} of them held constant beyond a column's first or last "
                        "finite value (extrapolated, not interpolated)") if n_held else ""
                repairs.append(
                    f"nonfinite='interpolate': filled {n_bad} non-finite value(s) in "
                    f"{bad_rows.size} frame(s) by linear interpolation in time{held}"
                )
        if repairs:
            previous = meta.get("repairs", [])
            meta["repairs"] = (list(previous) if isinstance(previous, list) else [previous]) + (
                repairs
            )

        self._coeffs = arr
        self._rate = rate
        self._timestamps = t
        self._start_time = float(t[0]) if t is not None else start_time
        self._modes = mode_list
        self._convention = convention
        self._units = units
        self._wavelength = wavelength
        self._metadata = meta
        self._repairs = tuple(repairs)
        self._fingerprint = None
        if t is not None and rate is None:
            # last, after every refusal of this constructor: a refused log is not warned
            _warn_timestamps_rate(t)

    # ------------------------------------------------------------------ construction
    def _derive(self, **changes: Any) -> ModalLog:
        """Return a copy with some private fields replaced, skipping validation.

        Preconditions: the caller passes values that are already valid and mutually
        consistent (e.g. ``_coeffs`` rows match ``_timestamps``).
        """
        new = object.__new__(ModalLog)
        # ModalLog's own fields, not ``self.__slots__``: a subclass declaring ``__slots__``
        # of its own hides them (adversarial round 23 PART a, d19)
        for name in ModalLog.__slots__:
            object.__setattr__(new, name, changes.pop(name, getattr(self, name)))
        if changes:  # pragma: no cover - programming error
            raise AttributeError(f"unknown fields {sorted(changes)}")
        new._modes = list(new._modes)
        new._metadata = copy.deepcopy(new._metadata)
        new._repairs = ()
        new._fingerprint = None  # other data, times or labels
        return new

    def __getstate__(self) -> dict:
        # every slot of the class and its subclasses and a subclass's ``__dict__``:
        # ``self.__slots__`` alone is a subclass's own (often empty) tuple, which pickled
        # nothing (adversarial round 23 PART a, d9 / d16)
        names = [n for cls in type(self).__mro__ for n in cls.__dict__.get("__slots__", ())
                 if n not in ("__dict__", "__weakref__")]
        state = {name: getattr(self, name) for name in names if hasattr(self, name)}
        state.update(getattr(self, "__dict__", {}))
        return state

    def __setstate__(self, state: dict | tuple) -> None:
        if isinstance(state, tuple):  # ``(dict, slots)``: pickled before ``__getstate__``
            state = {**(state[0] or {}), **(state[1] or {})}
        for name, value in state.items():
            object.__setattr__(self, name, value)
        self._fingerprint = None  # a copy in memory, no longer the read-only map it was
        for arr in (self._coeffs, self._timestamps):
            if isinstance(arr, np.ndarray) and arr.flags.writeable:
                arr.flags.writeable = False  # unpickled copies stay read-only

    def __eq__(self, other: object) -> bool:
        """Tell whether two logs hold the same log: values and everything that describes them.

        Coefficients bit for bit (same dtype and shape), the time axis as stored (rate,
        timestamps, start time), modes, convention, units, wavelength and metadata. Before,
        ``==`` was identity: a log read back exactly (``io.load(io.save(log))``), its pickle
        or copy, and a ``SimulationResult`` saved and loaded all compared unequal to the
        original (audit 10, feedback, row cl-save-load-eq). ``repairs`` (what building
        this object did) is not compared: the metadata keeps it. Logs are unhashable.
        """
        if not isinstance(other, ModalLog):
            return NotImplemented
        if self is other:
            return True
        a, b = self._coeffs, other._coeffs
        if a.dtype != b.dtype or a.shape != b.shape:
            return False
        ta, tb = self._timestamps, other._timestamps
        if (ta is None) != (tb is None) or (ta is not None and not np.array_equal(ta, tb)):
            return False
        return (self._rate == other._rate and self._start_time == other._start_time
                and list(self._modes) == list(other._modes)
                and self._convention == other._convention and self._units == other._units
                and self._wavelength == other._wavelength
                and same_value(self._metadata, other._metadata)
                and all(np.array_equal(x, y, equal_nan=True)
                        for x, y in zip(self.iter_chunks(65536), other.iter_chunks(65536),
                                        strict=True)))

    __hash__ = None  # type: ignore[assignment]  # equal by value, so not hashable

    # ------------------------------------------------------------------ properties
    @property
    def coeffs(self) -> np.ndarray:
        """Coefficients ``(T, M)``, read-only (may be a ``numpy.memmap``)."""
        return self._coeffs

    @property
    def dtype(self) -> np.dtype:
        """Floating dtype of the coefficients (float32 or float64)."""
        return self._coeffs.dtype

    @property
    def n_frames(self) -> int:
        """Number of frames ``T``."""
        return int(self._coeffs.shape[0])

    @property
    def n_modes(self) -> int:
        """Number of modes ``M``."""
        return int(self._coeffs.shape[1])

    @property
    def shape(self) -> tuple[int, int]:
        """``(T, M)``."""
        return (self.n_frames, self.n_modes)

    @property
    def rate(self) -> float | None:
        """Sample rate in Hz: as given, else the mean rate of the timestamps, else None."""
        if self._rate is not None:
            return self._rate
        t = self._timestamps
        if t is not None and t.shape[0] > 1:
            return float((t.shape[0] - 1) / (t[-1] - t[0]))
        return None

    @property
    def timestamps(self) -> np.ndarray | None:
        """Explicit frame times in seconds, or None when the time axis comes from ``rate``."""
        return self._timestamps

    @property
    def start_time(self) -> float:
        """Time of the first frame in seconds."""
        return self._start_time

    @property
    def times(self) -> np.ndarray | None:
        """Frame times ``(T,)`` in seconds (None if the log has no rate nor timestamps)."""
        if self._timestamps is not None:
            return self._timestamps
        if self._rate is None:
            return None
        return self._start_time + np.arange(self.n_frames, dtype=np.float64) / self._rate

    @property
    def duration(self) -> float | None:
        """Time span covered in seconds (None without a time axis).

        ``n_frames / rate``; for timestamps with gaps or short intervals, the span
        ``t[-1] - t[0]`` plus one median interval (``n_frames`` over the mean rate
        stretched the span by ``n / (n - 1)``: two nights 8 h apart in 3000 frames
        showed 28810.4 s for 28800.75 s, audit 10-time).
        """
        t = self._timestamps
        if t is not None and t.shape[0] > 1:
            s = self.sampling()
            if not s.uniform:
                return float(t[-1] - t[0]) + s.median_interval
        rate = self.rate
        if rate is None:
            return 0.0 if self._timestamps is not None else None
        return self.n_frames / rate

    @property
    def modes(self) -> list:
        """Mode of each column: int indices in ``convention`` or str labels."""
        return list(self._modes)

    @property
    def labels(self) -> list[str]:
        """Column labels: ``"Z4"`` (Noll), ``"A4"`` (ANSI), ``"F4"`` (Fringe) or the labels."""
        return mode_labels(self._modes, self._convention)

    @property
    def convention(self) -> str:
        """Indexing convention of ``modes``."""
        return self._convention

    @property
    def units(self) -> str:
        """Units of the coefficients: "rad", "nm", "um" or "waves"."""
        return self._units

    @property
    def wavelength(self) -> float | None:
        """Wavelength in metres at which phase is defined, or None."""
        return self._wavelength

    @property
    def metadata(self) -> dict:
        """A copy of the free-form metadata dict."""
        return copy.deepcopy(self._metadata)

    @property
    def repairs(self) -> tuple[str, ...]:
        """Repairs made when this log was built (non-finite handling)."""
        return self._repairs

    def __len__(self) -> int:
        return self.n_frames

    def __repr__(self) -> str:
        rate = "unknown" if self.rate is None else f"{self.rate:g} Hz"
        labels = self.labels
        shown = ", ".join(labels[:4]) + (", ..." if len(labels) > 4 else "")
        return (
            f"ModalLog({self.n_frames} frames x {self.n_modes} modes [{shown}], "
            f"{self._convention}, {self._units}, rate={rate}, dtype={self.dtype})"
        )

    # ------------------------------------------------------------------ selection
    def __getitem__(self, key) -> ModalLog:
        """Frames ``log[i0:i1:step]`` (positive step) as a new log."""
        if not isinstance(key, slice):
            raise TypeError(
                f"a ModalLog is indexed by a frame slice such as log[10:100]; got {key!r} "
                "(use log.coeffs for array indexing, log.select(modes=...) for modes)."
            )
        start, stop, step = key.indices(self.n_frames)
        if step <= 0:
            raise ValueError(f"frame slice step must be positive; got {step}.")
        if len(range(start, stop, step)) == 0:
            raise ValueError(
                f"frame slice {key} selects no frame of a log with {self.n_frames} frames."
            )
        return self._take_frames(slice(start, stop, step))

    def _take_frames(self, sl: slice) -> ModalLog:
        changes: dict[str, Any] = {"_coeffs": self._coeffs[sl]}
        if self._timestamps is not None:
            t = self._timestamps[sl]
            changes["_timestamps"] = t
            changes["_start_time"] = float(t[0])
            if self._rate is not None and sl.step != 1:
                changes["_rate"] = self._rate / sl.step
        elif self._rate is not None:
            changes["_start_time"] = self._start_time + sl.start / self._rate
            changes["_rate"] = self._rate / sl.step
        return self._derive(**changes)

    def _time_index(self, when: float) -> int:
        """First frame index whose time is >= ``when``."""
        if self._timestamps is not None:
            return int(np.searchsorted(self._timestamps, when, side="left"))
        i = math.ceil((when - self._start_time) * self._rate)
        i = min(max(i, 0), self.n_frames)

        def time(k):
            return self._start_time + k / self._rate

        while i > 0 and time(i - 1) >= when:
            i -= 1
        while i < self.n_frames and time(i) < when:
            i += 1
        return i

    def _column_indices(self, modes, name: str) -> list[int]:
        if isinstance(modes, str | numbers.Integral):
            modes = [modes]
        try:
            wanted = list(modes)
        except TypeError as exc:
            raise TypeError(f"`{name}` must be a sequence of modes; got {modes!r}.") from exc
        labels = self.labels
        out = []
        for item in wanted:
            if isinstance(item, bool):
                raise TypeError(f"`{name}` entries must be mode indices or labels; got {item!r}.")
            if isinstance(item, numbers.Integral) and self._convention != "labels":
                key = int(item)
                if key in self._modes:
                    out.append(self._modes.index(key))
                    continue
            elif isinstance(item, str):
                found = find_label(labels, item)  # by NFC: round 21 PART b, u11
                if found is not None:
                    out.append(found)
                    continue
            elif isinstance(item, numbers.Integral):
                # "must be mode indices or labels; got 0" named an index as if it were
                # none (round 36 PART a, W1)
                raise TypeError(
                    f"`{name}` entries of a log with convention='labels' must be its labels "
                    f"({mode_span(self._modes, self._convention, sep='..')}); got the "
                    f"index {item!r}.")
            else:
                raise TypeError(f"`{name}` entries must be mode indices or labels; got {item!r}.")
            ends = item.split("-") if isinstance(item, str) else []
            if len(ends) == 2 and all(find_label(labels, e.strip()) is not None for e in ends):
                # 'Z2-Z4' was "not a mode of this log; its modes are Z2..Z11" (round 41
                # PART b, F08): both ends are
                raise ValueError(
                    f"`{name}` entry {item!r}: a range is read between mode indices "
                    f"('2-4'), not labels; {ends[0].strip()} and {ends[1].strip()} are "
                    "modes of this log: give their indices or list the labels "
                    "('Z2,Z3,Z4').")
            raise ValueError(
                f"`{name}` entry {item!r} is not a mode of this log; its modes are "
                f"{mode_span(self._modes, self._convention, sep='..')} ({self._convention})."
            )
        return out

    def _take_modes(self, columns: list[int]) -> ModalLog:
        if not columns:
            raise ValueError("the selection leaves no mode; a log needs at least one.")
        cols = np.asarray(columns)
        n = self.n_modes
        if cols.size and np.array_equal(cols, np.arange(cols[0], cols[0] + cols.size)):
            data = self._coeffs[:, cols[0] : cols[0] + cols.size]  # a view (no copy)
            if cols.size == n:
                data = self._coeffs
        else:
            data = np.ascontiguousarray(self._coeffs[:, cols])
            data.flags.writeable = False
        return self._with_columns_of(self._derive(
            _coeffs=data, _modes=[self._modes[c] for c in columns]), columns)

    def _with_columns_of(self, new: ModalLog, columns) -> ModalLog:
        """Return ``new`` (columns ``columns`` of this log) with its per-column metadata.

        ``metadata["modes_identification"]`` (which Zernike each of a file's mode images
        is, per column) followed the file's columns through a selection or a convention
        change: `info` then named the wrong Zernike per column (adversarial round 32
        PART b, b12). An identification of another width is dropped, not guessed.
        """
        ident = new._metadata.get("modes_identification")
        if not isinstance(ident, dict):
            return new
        from modalinfo.bases.identify import ZernikeIdentification

        meta = dict(new._metadata)
        try:
            whole = ZernikeIdentification.from_dict(ident)
            if whole.n_modes != self.n_modes:
                raise ValueError("another width")
            meta["modes_identification"] = whole.take(list(columns)).to_dict()
        except ValueError:
            del meta["modes_identification"]
        new._metadata = meta
        return new

    def select(self, modes=None, time=None) -> ModalLog:
        """Return the log restricted to some modes and/or a time window.

        Parameters
        ----------
        modes : sequence of int or str, optional
            Modes to keep, in the wanted column order: indices in the log's convention
            or labels (``"Z4"``).
        time : tuple of (float or None, float or None), optional
            ``(t0, t1)`` in seconds; keeps frames with ``t0 <= t < t1`` (None = open).

        Returns
        -------
        ModalLog
            A new log (coefficients are a view where possible).

        Raises
        ------
        ValueError
            Unknown mode, empty selection, or a time window on a log with no time axis.
        """
        out = self
        if modes is not None:
            columns = out._column_indices(modes, "modes")
            if len(set(columns)) != len(columns):
                raise ValueError(f"`modes` must not name a mode twice; got {modes!r}.")
            out = out._take_modes(columns)
        if time is not None:
            if out.times is None:
                raise ValueError(
                    "`time` selection needs a time axis; this log has no rate nor timestamps."
                )
            try:
                t0, t1 = time
            except (TypeError, ValueError) as exc:
                raise TypeError(
                    f"`time` must be a pair (t0, t1) in seconds; got {time!r}."
                ) from exc
            i0 = 0 if t0 is None else out._time_index(check_real(t0, "time[0]"))
            i1 = out.n_frames if t1 is None else out._time_index(check_real(t1, "time[1]"))
            if i1 <= i0:
                raise ValueError(
                    f"`time` window {time!r} s selects no frame (log spans "
                    f"{out.times[0]!r} .. {out.times[-1]!r} s)."
                )
            out = out._take_frames(slice(i0, i1, 1))
        return out

    def drop_modes(self, modes) -> ModalLog:
        """Return the log without the given modes.

        Parameters
        ----------
        modes : int, str or sequence of int or str
            Modes to remove: indices in the log's convention or labels (``"Z4"``).

        Returns
        -------
        ModalLog
            The remaining columns in their order.

        Raises
        ------
        ValueError
            A mode not in the log, or no mode left.
        """
        drop = set(self._column_indices(modes, "modes"))
        return self._take_modes([c for c in range(self.n_modes) if c not in drop])

    def without_piston_tiptilt(self) -> ModalLog:
        """Return the log without piston, tip and tilt (those of them it holds)."""
        if self._convention == "labels":
            raise ValueError(
                "without_piston_tiptilt needs Zernike modes; this log has convention='labels'."
            )
        ptt = set(PISTON_TIPTILT[self._convention])
        return self._take_modes([c for c, j in enumerate(self._modes) if j not in ptt])

    # ------------------------------------------------------------------ conversions
    def to_units(self, units: str, wavelength: float | None = None) -> ModalLog:
        """Return the log in other units.

        Parameters
        ----------
        units : {"rad", "nm", "um", "waves"}
            Target units.
        wavelength : float, optional
            Wavelength in metres. Needed between phase (rad, waves) and OPD (nm, um)
            if the log has none. When converting *from* phase it must equal the log's
            wavelength (the one the phase is defined at); converting from OPD it sets
            the wavelength of the resulting phase.

        Returns
        -------
        ModalLog
            Same dtype; ``phase[rad] = 2 pi OPD / lambda``, ``waves = OPD / lambda``.

        Raises
        ------
        ValueError
            If the log's units were assumed (``metadata["assumed"]["units"]``: its file
            does not record them) and ``units`` differs: the factor would be a guess.
            ``modalinfo convert`` refuses the same (``--in-units``).
        """
        units = check_units(units)
        assumed = self._metadata.get("assumed")
        if isinstance(assumed, dict) and "units" in assumed and units != self._units:
            # the converted log would read as known units while its scale is a guess
            # (audit 9, files: it kept metadata 'assumed: rad' beside units nm)
            raise ValueError(
                f"`units`: this log's units ({self._units}) were assumed, not recorded by "
                f"its file, so converting to {units!r} would scale by a guess; state them "
                "when loading (load(..., units=...), the command line's --in-units).")
        lam = self._wavelength
        if wavelength is not None:
            wavelength = check_wavelength(wavelength)
            if (
                lam is not None
                and self._units in ("rad", "waves")
                and not math.isclose(wavelength, lam, rel_tol=1e-12)
            ):
                raise ValueError(
                    f"`wavelength` ({wavelength} m) differs from the wavelength this log's phase "
                    f"is defined at ({lam} m); convert to 'nm' first to change wavelength."
                )
            lam = wavelength
        factor = unit_scale(self._units, units, lam)
        if factor == 1.0:
            data = self._coeffs
        else:
            _check_converted_range(self._coeffs, factor, self._units, units)
            data = np.multiply(self._coeffs, self._coeffs.dtype.type(factor))
            data.flags.writeable = False
        new = self._derive(_coeffs=data, _units=units, _wavelength=lam)
        if units != self._units and "units_note" in new._metadata:
            # a free-text note on the old units ("coefficients in rad of phase ...") would
            # contradict the new ones: ``convert --units waves`` kept it (round 17 PART b)
            new._metadata["units_note"] = (f"converted from {self._units} to {units}; "
                                           f"before: {new._metadata['units_note']}")
        return new

    def to_convention(self, convention: str) -> ModalLog:
        """Return the log with modes re-indexed in another Zernike convention.

        Columns are renamed and reordered by increasing index of the new convention;
        values are unchanged since every convention here is unit-RMS normalised.

        Parameters
        ----------
        convention : {"noll", "ansi", "fringe"}
            Target convention.

        Returns
        -------
        ModalLog
            The re-indexed log.
        """
        if not isinstance(convention, str):
            raise TypeError(f"`convention` must be a str; got {convention!r}.")
        convention = check_choice(convention.lower(), "convention", CONVENTIONS)
        if convention == self._convention:
            return self
        if "labels" in (convention, self._convention):
            raise ValueError(
                f"cannot convert convention {self._convention!r} to {convention!r}: "
                "labelled (non-Zernike) modes have no index in another convention."
            )
        from modalinfo.bases import (
            ansi_to_noll,
            fringe_to_noll,
            noll_to_ansi,
            noll_to_fringe,
        )

        to_noll = {"noll": lambda j: j, "ansi": ansi_to_noll, "fringe": fringe_to_noll}
        from_noll = {"noll": lambda j: j, "ansi": noll_to_ansi, "fringe": noll_to_fringe}
        src = np.asarray(self._modes, dtype=np.int64)
        new = np.asarray(from_noll[convention](to_noll[self._convention](src)), dtype=np.int64)
        order = np.argsort(new, kind="stable")
        data = np.ascontiguousarray(self._coeffs[:, order])
        data.flags.writeable = False
        return self._with_columns_of(self._derive(
            _coeffs=data, _modes=[int(new[k]) for k in order], _convention=convention
        ), [int(k) for k in order])

    def with_metadata(self, **items: Any) -> ModalLog:
        """Return a copy whose metadata is updated with ``items``.

        Parameters
        ----------
        **items
            Entries to add or replace; JSON-serialisable, no NaN or infinity.

        Returns
        -------
        ModalLog
            Same coefficients, new metadata.
        """
        meta = dict(self._metadata)
        meta.update(items)
        return self._derive(_metadata=check_metadata(meta))

    # ------------------------------------------------------------------ sampling
    def sampling(self, gap_factor: float = 1.5):
        """Median rate, jitter and gaps of the timestamps (None without timestamps).

        Parameters
        ----------
        gap_factor : float
            An interval longer than ``gap_factor`` median intervals is a gap.

        Returns
        -------
        modalinfo.telemetry.sampling.Sampling or None
            None when the time axis comes from ``rate`` (uniform by construction) or
            the log has no time axis.
        """
        from modalinfo.telemetry.sampling import sampling_of

        if self._timestamps is None:
            return None
        return sampling_of(self._timestamps, gap_factor)

    def segments(self, gap_factor: float = 1.5) -> list[tuple[int, int]]:
        """Contiguous frame ranges ``[(start, stop), ...]`` between timestamp gaps.

        A log without timestamps is one segment ``[(0, T)]``.
        """
        s = self.sampling(gap_factor)
        return [(0, self.n_frames)] if s is None else s.segments

    def longest_segment(self, gap_factor: float = 1.5) -> ModalLog:
        """Return the longest run of frames without a timestamp gap (the log if none).

        Returns
        -------
        ModalLog
            ``log[start:stop]``; ``metadata["segment"]`` records the frames kept.
        """
        segs = self.segments(gap_factor)
        if len(segs) == 1:
            return self
        start, stop = max(segs, key=lambda ab: ab[1] - ab[0])
        out = self._take_frames(slice(start, stop, 1))
        meta = dict(out._metadata)
        meta["segment"] = (
            f"frames {start}..{stop - 1} of {self.n_frames}: the longest of {len(segs)} "
            "contiguous segments"
        )
        return out._derive(_metadata=meta)

    def iter_chunks(self, n_frames: int) -> Iterator[np.ndarray]:
        """Yield the coefficients in consecutive blocks of at most ``n_frames`` frames.

        For a memory-mapped log the pages of a block are released after the consumer
        asks for the next one, so iterating a log larger than memory keeps the
        resident set small.

        Parameters
        ----------
        n_frames : int
            Frames per block, ``>= 1``.

        Yields
        ------
        numpy.ndarray
            Read-only views ``(n, M)``, ``n <= n_frames``, in the log's units.
        """
        n_frames = check_int(n_frames, "n_frames", minimum=1)
        return row_blocks(self._coeffs, n_frames)


def _check_converted_range(coeffs: np.ndarray, factor: float, old: str, new: str) -> None:
    """Refuse a unit conversion whose product leaves the coefficients' float range.

    ``to_units`` multiplies by ``factor`` in the log's own dtype; a log of 1e307 rad came
    back as a log of inf nm with only numpy's overflow RuntimeWarning (a float32 log
    from 4.3e36 rad), a log the constructor would have refused (round 40 PART a, L11).
    """
    if coeffs.size == 0:
        return
    top = float(np.finfo(coeffs.dtype).max)
    peak = 0.0
    for start in range(0, coeffs.shape[0], 65536):  # a memory map stays on disk
        block = coeffs[start : start + 65536]
        if block.size:
            peak = max(peak, float(np.max(np.abs(block))))
    if peak * factor > top:
        raise ValueError(
            f"`units`: converting from {old!r} to {new!r} multiplies by {factor:.4g}, and "
            f"the largest coefficient, {peak:.3g} {old}, would exceed the {coeffs.dtype} "
            f"range ({top:.3g}); the values are not a wavefront in {old} (check the "
            "log's units or its scale).")
