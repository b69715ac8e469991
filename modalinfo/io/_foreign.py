"""Rules for files written by other software: layout, relabelling hints, time axis.

A file written by modalinfo describes itself completely; a *foreign* file (a bare
array, a CSV, a FITS image, an HDF5 dataset) does not, and the reader must neither
guess silently nor refuse what the caller states. The rules, applied by
:func:`modalinfo.io._common.build_log`:

* **Layout.** Logs are ``(T frames, M modes)``. A stored array that looks like
  ``(M, T)`` is refused with the fix unless the file or the caller says which way
  round it is: the hint ``transpose=True`` (read the array transposed) or
  ``transpose=False`` (as stored), or an axis annotation in the file (FITS
  ``CTYPE1``/``CTYPE2``, an HDF5 dataset attribute ``axes``/``dims``/
  ``dimension_labels``, dimension labels, or the names of the dimension scales attached
  to its axes as netCDF-4 writes them). It looks transposed when it has
  more columns than rows and either more than :data:`MAX_MODES` columns or at least
  :data:`COLUMN_RATIO` times as many columns as rows (and more than
  :data:`MIN_SUSPECT_COLUMNS`), or when a ``modes`` hint or the file's time axis has
  one entry per *row*, or when the writer stores arrays column-major (a MATLAB v7.3
  variable: ``stored["_column_major"]``, whatever its shape). Column names (a CSV
  header row, table columns) or a ``modes`` hint with one entry per column confirm the
  stored layout. A transposition is
  recorded in ``metadata["layout"]``. Where nothing but the shape speaks for the stored
  layout (no annotation, hint, column names or time axis) and the shape fits either way
  round (read transposed, it would not look transposed either), the content is asked
  (``modalinfo.telemetry.checks.layout_doubt``: lag-1 autocorrelation along each axis):
  an array whose columns decorrelate slower from column to column than from row to row
  is read as stored with a ``LayoutWarning`` naming ``--transpose``, and
  ``metadata["layout"]["doubt"]`` says so (issue 27, left31-orient).
* **Relabelling.** Modes and convention read from foreign column names may be
  replaced by ``modes=`` / ``convention=`` hints (recorded in
  ``metadata["relabelled"]``) instead of being refused as a contradiction.
* **Time axis.** An explicit ``rate=`` wins over foreign timestamps that disagree
  with it (recorded in ``metadata["time_axis"]``); frame-number columns become
  times ``frame / rate`` only with a rate.
* **A rate field beside timestamps.** A foreign rate (an NPZ member, an HDF5 dataset or
  attribute, a FITS keyword named as in :data:`RATE_FIELD_NAMES`) is never read: the
  timestamps set the time axis. Where it disagrees with them by more than their own
  jitter, ``metadata["rate_field"]`` says so, and the command lines print it once
  (Leftovers 19-misc; round 19 PART b, B10, B12, B17).
* **Assumed values.** Every value neither read from the file nor given by the
  caller (units ``rad``, convention ``noll``, the default modes) is listed in
  ``metadata["assumed"]``.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from modalinfo.common.files import quoted
from modalinfo.common.quiet import caller_stacklevel, warn
from modalinfo.io.files import LogFormatError
from modalinfo.telemetry.checks import (
    COLUMN_RATIO,
    MAX_MODES,
    MIN_SUSPECT_COLUMNS,
    LayoutWarning,
    layout_doubt,
    mode_span,
    transposed_shape,
)

__all__ = ["MAX_MODES", "COLUMN_RATIO", "MIN_SUSPECT_COLUMNS", "RATE_FIELD_NAMES", "orient",
           "axis_layout", "rate_field"]

_TIME_WORDS = {"time", "times", "t", "frame", "frames", "sample", "samples", "epoch",
               "timestamp", "timestamps", "iteration", "iterations", "step", "steps"}
_MODE_WORDS = {"mode", "modes", "zernike", "zernikes", "coefficient", "coefficients",
               "coeff", "coeffs", "noll", "kl", "actuator", "actuators", "index"}


#: Names of a foreign file's rate field [Hz] (case, ``-`` and ``_`` ignored; FITS
#: keywords have at most 8 characters: ``FRAMERAT``, ``SAMPRATE``).
RATE_FIELD_NAMES = frozenset({"rate", "framerate", "framerat", "samplerate", "samprate",
                              "samplingrate", "looprate"})


def rate_field(fields, where: str) -> tuple[float, str] | None:
    """Return ``(rate, description)`` of the first rate field among ``fields``, else None.

    ``fields`` maps names to values (NPZ members, HDF5 datasets or attributes, a FITS
    header); a field counts when its name is in :data:`RATE_FIELD_NAMES` and it holds
    one finite positive number. ``where`` names the kind of field (``"member"``).
    """
    for name in list(fields.keys()):
        key = str(name).rsplit("/", 1)[-1].strip().lower().replace("-", "").replace("_", "")
        if key not in RATE_FIELD_NAMES:
            continue
        try:
            item = fields[name]
            if getattr(item, "size", 1) != 1:  # a per-frame array is no rate field
                continue
            value = np.asarray(item[()] if hasattr(item, "shape") else item)
        except (TypeError, ValueError, OSError, KeyError):
            continue
        if value.dtype.kind not in "fiu" or value.size != 1:
            continue
        rate = float(value.reshape(()))
        if np.isfinite(rate) and rate > 0:
            return rate, f"{where} {str(name)!r}"
    return None


def _word(text: Any) -> str | None:
    if isinstance(text, bytes):
        text = text.decode("utf-8", "replace")
    if not isinstance(text, str):
        return None
    key = text.strip().lower().replace("-", "").replace("_", "")
    if key in {w.replace("_", "") for w in _TIME_WORDS}:
        return "time"
    if key in _MODE_WORDS:
        return "mode"
    return None


def axis_layout(names: list, source: str) -> tuple[str, str] | None:
    """Return ``(layout, reason)`` from two axis names in numpy order, else None.

    ``names[0]`` labels the rows (axis 0), ``names[1]`` the columns. The layout is
    ``"frames_first"`` or ``"modes_first"``; ``reason`` quotes ``source``.
    """
    if len(names) != 2:
        return None
    kinds = [_word(n) for n in names]
    if kinds == ["time", "mode"]:
        return "frames_first", source
    if kinds == ["mode", "time"]:
        return "modes_first", source
    return None


#: What :func:`_evidence` returns when nothing but the shape speaks for the layout.
_GUESSED = ""


def _evidence(shape: tuple[int, int], stored: dict, hints: dict) -> str | None:
    """Why a foreign ``(rows, cols)`` array looks transposed (None: it does not).

    ``_GUESSED`` (an empty string) when neither the file nor the caller confirms the
    stored layout and the shape does not speak against it: the layout is a guess.
    """
    n_rows, n_cols = shape
    modes = hints.get("modes")
    if modes is not None and not isinstance(modes, str | bytes):
        try:
            n = len(modes)
        except TypeError:
            n = None
        if n == n_cols:
            return None  # the caller names every column: the layout is confirmed
        if n == n_rows:
            return f"the modes hint names {n} modes, one per row"
    if "modes" in stored:
        return None  # the file names its columns
    times = stored.get("timestamps")
    if times is None:
        times = stored.get("_frame_numbers")
    if times is not None and np.ndim(times) == 1:
        if len(times) == n_rows:
            return None
        if len(times) == n_cols:
            return f"its time axis has {n_cols} entries, one per column"
    # the shape rule ModalLog applies too
    return transposed_shape(n_rows, n_cols) or _GUESSED


def orient(coeffs, path: Path, stored: dict, hints: dict) -> tuple[Any, dict | None]:
    """Apply the layout rule; return the ``(T, M)`` array and the metadata record.

    ``stored["_layout"]`` is an annotation ``(layout, reason)`` read from the file;
    ``hints["transpose"]`` the caller's statement. Raises ``LogFormatError`` for a
    likely transposed array nobody vouched for, ``ValueError`` for a hint
    contradicting the file's annotation.
    """
    transpose = hints.get("transpose")
    if transpose is not None and not isinstance(transpose, bool | np.bool_):
        raise TypeError(f"hint `transpose` must be a bool; got {transpose!r}.")
    annotation = stored.get("_layout")
    if np.ndim(coeffs) != 2:
        return coeffs, None  # ModalLog reports the wrong dimensions
    if annotation is not None:
        layout, reason = annotation
        if transpose is not None and bool(transpose) != (layout == "modes_first"):
            raise ValueError(
                f"hint `transpose`={bool(transpose)} contradicts {quoted(path)}, whose {reason} "
                "says the array is stored "
                f"{'modes x frames' if layout == 'modes_first' else 'frames x modes'}."
            )
        if layout == "modes_first":
            return coeffs.T, {"stored": "modes x frames", "transposed": f"by {reason}"}
        return coeffs, None
    if transpose:
        return coeffs.T, {"stored": "modes x frames", "transposed": "by the hint transpose=True"}
    if transpose is False:
        return coeffs, None
    why = _evidence(coeffs.shape, stored, hints)
    if not why and stored.get("_column_major"):
        why = stored["_column_major"]  # the writer's order, not the shape, is in doubt
    if why == _GUESSED:
        # nothing vouches for the layout and the shape fits either way round: the content
        # may tell (left31-orient); a lopsided array (400,000 x 27) is not read at all
        if transposed_shape(*reversed(np.shape(coeffs))) is None:
            return coeffs, _content_doubt(coeffs, path)
        return coeffs, None
    if why is not None:
        n_rows, n_cols = coeffs.shape
        raise LogFormatError(
            f"{quoted(path)} holds a {n_rows} x {n_cols} array that looks transposed (modes x "
            f"frames): {why}; pass transpose=True (command line: --transpose) to read "
            f"{n_cols} frames of {n_rows} modes, or transpose=False (--no-transpose) to "
            f"keep {n_rows} frames of {n_cols} modes"
        )
    return coeffs, None


def _content_doubt(coeffs, path: Path) -> dict | None:
    """Warn (``LayoutWarning``) where a guessed layout's content says modes x frames.

    ``modalinfo.telemetry.checks.layout_doubt`` is the rule; the returned record (None:
    no doubt) goes to ``metadata["layout"]``, so a ``batch`` row names it too.
    """
    found = layout_doubt(coeffs)
    if found is None:
        return None
    m0, m1, threshold = found
    n_rows, n_cols = np.shape(coeffs)
    text = (f"{quoted(Path(path).name)} was read as {n_rows} frames x {n_cols} modes (no axis "
            "names; either way round fits its shape), but its content says modes x frames: "
            f"lag-1 autocorrelation {m1:.2f} from column to column, {m0:.2f} from row to "
            "row (a log's modes persist in time, not across mode numbers; IDL, MATLAB and "
            "Fortran put the frames on the first FITS / array axis); pass transpose=True "
            f"(--transpose) to read {n_cols} frames of {n_rows} modes, or transpose=False "
            "(--no-transpose) to keep this layout")
    warn(text, LayoutWarning, stacklevel=caller_stacklevel())
    return {"stored": "frames x modes (guessed)",
            "doubt": f"looks modes x frames: lag-1 {m1:.2f} from column to column, "
                     f"{m0:.2f} from row to row"}


def describe_modes(modes: list, convention: str) -> str:
    """``"Z2..Z28 (noll)"``-style text for metadata records."""
    return f"{mode_span(list(modes), convention, sep='..')} ({convention})"
