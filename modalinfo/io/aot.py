"""AO Telemetry (AOT) files, read and written with ``aotpy``: one control loop as a ``ModalLog``.

An AOT file (FITS; primary keyword ``AOT-VERS``) describes a whole AO system. The
reader returns the log of one *control loop*:

* coefficients: the loop's ``modal_coefficients`` ``(t, m)``; when it has none but
  its sensor has ``measurements`` ``(t, d, s_v)`` and the loop a
  ``measurements_to_modes`` ``(m, d, s_v)``, their product (stated in
  ``metadata["coefficients"]``; reference measurements are not subtracted);
* time: the coefficients' (or the loop's) ``Time`` timestamps [s] and the loop's
  ``framerate`` [Hz] (dropped, and kept in metadata, if it disagrees with the
  timestamps);
* units: the coefficient image's ``BUNIT`` when it is one of ours (``"m"`` is
  converted to ``"nm"``, said in metadata); otherwise the file does not say and the
  caller may pass ``units=``;
* modes: when the loop has ``modes`` (m images), they are identified as Zernikes of
  our convention (:func:`modalinfo.bases.identify.identify_zernike`); the columns are
  labelled with their Noll indices when every mode is a distinct positive Zernike,
  else with the labels of the coefficient image's ``MI_MODES`` card (closedloop's
  export of a DM-space K-L or zonal mirror: ``DMKL1``...; also for a loop without mode
  images), else ``"mode1"``... (``convention="labels"``); the identification is in
  ``metadata["modes_identification"]`` and :func:`read_aot_basis` gives the basis;
* metadata: system, telescope diameter, sensor type and subapertures, corrector,
  delay [frames], time filter, loop state, the file's control loops.

Files written by :func:`write_aot` carry the log's own header (JSON card ``MI_JSON``
on the coefficient image), so ``load(save(log))`` gives the log back exactly: same
coefficients (float32 or float64, bit for bit: AOT images keep their dtype),
timestamps (float64), rate, modes, units, wavelength and metadata.

Several loops: choose with ``loop=UID``; the error lists the uids.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import re
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from modalinfo.common.files import as_path, atomic_write, check_readable, quoted
from modalinfo.common.quiet import catching_warnings
from modalinfo.common.sizes import format_size
from modalinfo.io._columns import FITS_UNITS, UNIT_WORDS, unit_word
from modalinfo.io._common import (
    build_log,
    dumps,
    log_header,
    parse_header,
    reading,
    stored_from_header,
    unwrap,
)
from modalinfo.io.aot_system import (
    CorrectorSpec,
    LoopSpec,
    SensorSpec,
    TelescopeSpec,
    build_system,
    config_of,
    geometry_of,
    import_aotpy,
)
from modalinfo.io.files import LogFormatError
from modalinfo.io.fits_size import check_whole
from modalinfo.telemetry.log import ModalLog
from modalinfo.telemetry.sampling import rate_agrees
from modalinfo.telemetry.units import WAVELENGTH_RANGE

__all__ = [
    "is_aot",
    "aot_loops",
    "check_aot_size",
    "estimate_write_aot",
    "read_aot",
    "read_aot_basis",
    "read_aot_system",
    "write_aot",
    "write_system",
]

_JSON_KEY = "MI_JSON"
#: card on a loop's coefficient image: its columns' labels (JSON list), written by
#: closedloop's export for modes that are not Noll Zernikes (DM-space K-L, zonal)
_LABELS_KEY = "MI_MODES"
#: closedloop's export: the wavelength [m] of the coefficients' phase (rad)
_WAVELENGTH_KEY = "MI_WAVEL"
#: card of the coefficient image naming the units of every log :func:`write_aot` writes,
#: as ``modalinfo.io.fits`` writes it: a log in waves has no ``BUNIT`` (no FITS unit)
_UNITS_KEY = "MI_UNITS"
#: AOT ``BUNIT`` spellings of a coefficient image -> (our unit, factor to it): the words
#: every foreign reader knows (:data:`modalinfo.io._columns.UNIT_WORDS`). Any other unit
#: (``rad/s``, ``V``, ``pix``, ``furlong``...) is refused unless the caller states the units.
_UNIT_WORDS = UNIT_WORDS
_VERSION_KEY = "AOT-VERS"
_HEADER_BLOCKS = 36  # primary-header blocks scanned for AOT-VERS (100 kB)
#: bytes a FITS image extension adds to its data: a header of aotpy's cards (one or two
#: 2880-byte blocks) and the data's padding to a whole block (half a block on average)
HDU_OVERHEAD = 2.5 * 2880
#: the binary tables, primary header and small images of a file written through aotpy,
#: beyond the arrays an estimate counts [bytes] (closedloop's export: 60 blocks)
TABLE_BYTES = 60 * 2880
#: copies of the file's arrays :func:`write_aot` holds at once (the caller's, the image
#: handed to aotpy, astropy's big-endian copies while it writes and checksums): an upper
#: bound on tracemalloc's peaks, 3.87 copies for 20,000 x 50 float64 coefficients, 1.16
#: for float32 and 2.3 with 36 mode images of 128 x 128 pixels (left13-cli)
_WRITE_COPIES = 4.5


def is_aot(path) -> bool:
    """Tell whether a file is AOT: a FITS primary header holding ``AOT-VERS``.

    Only the primary header's 80-character cards are scanned (up to its ``END``);
    nothing is parsed beyond that.
    """
    path = as_path(path)
    try:
        with open(path, "rb") as fh:
            for _ in range(_HEADER_BLOCKS):
                block = fh.read(2880)
                if not block:
                    return False
                for i in range(0, len(block) - 79, 80):
                    key = block[i:i + 8].rstrip()
                    if key == _VERSION_KEY.encode() and block[i + 8:i + 10] == b"= ":
                        return True
                    if key == b"END":
                        return False
    except OSError:
        return False
    return False


@contextlib.contextmanager
def _aot_reading(path: Path) -> Iterator[list]:
    """Read inside: aotpy failures -> ``LogFormatError``; its warnings are collected."""
    with reading("AOT", path), catching_warnings(record=True) as caught:
        warnings.simplefilter("always")
        notes: list = []
        yield notes
        for item in caught:
            text = str(item.message).strip().splitlines()[0] if str(item.message) else ""
            low = text.lower()
            if any(w in low for w in ("checksum", "datasum", "truncated", "corrupt",
                                      "multiple of 2880", "extra bytes")):
                raise LogFormatError(f"corrupt AOT file {quoted(path)}: {text}")
            notes.append(text)


def read_aot_system(path, *, verify: bool = True):
    """Read an AOT file into an ``aotpy.AOSystem`` (errors name the file).

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    verify : bool
        Verify FITS checksums where the file has them.

    Returns
    -------
    aotpy.AOSystem
        The system.

    Raises
    ------
    LogFormatError
        Not an AOT file, truncated, or failing aotpy's verification.
    """
    return _read_system(as_path(path), verify)[0]


def _read_system(path: Path, verify: bool):
    """Return the system and aotpy's verification notes (its warnings, first lines)."""
    aotpy = import_aotpy()
    check_readable(path)
    _check_mapping(path)
    with _aot_reading(path) as notes:
        check_whole(path, "AOT")  # before aotpy, whose words name no truncation
        try:
            system = aotpy.AOSystem.read_from_file(path, file_type="fits",
                                                   checksum=bool(verify))
        except Exception as exc:  # aotpy's AOTVerificationException, among others
            said = _cut_between(path, exc)
            if said is None:
                raise
            raise LogFormatError(said) from None
    return system, notes


#: aotpy's words for an HDU the file lacks -> what that HDU is, in ours
_MISSING_HDU = (
    (re.compile(r"Missing mandatory table '([^']+)'"),
     lambda m: f"it has no table {m[1]!r}, which every AOT file has"),
    (re.compile(r"Table (\S+) does not exist even though there are rows of type (.+?) in "
                r"(\S+?)\."),
     lambda m: f"it has no table {m[1]!r}, which its {m[3]} rows of type {m[2]} need"),
    (re.compile(r"Image '([^']+)' not found in file"),
     lambda m: f"it has no image {m[1]!r}, which its tables refer to"),
)


def _cut_between(path: Path, exc: Exception) -> str | None:
    """Name an AOT file cut between two HDUs, from aotpy's "missing table" error.

    Such a file was "corrupt AOT file ...: AOTVerificationException: [AOTFITSFile] Missing
    mandatory table 'AOT_DETECTORS'" while a cut inside an HDU is named as one
    (``fits_size``); the sizes cannot see a cut at an HDU boundary, the missing table
    can (fix56-c). None when aotpy said something else, or the file does not end right
    after a whole HDU.
    """
    from modalinfo.io.fits_size import cut_between

    text = str(exc)
    for pattern, words in _MISSING_HDU:
        found = pattern.search(text)
        if found is not None:
            return cut_between(path, "AOT", words(found))
    return None


def _check_mapping(path: Path) -> None:
    """Refuse a file larger than the address space left, before astropy maps it whole.

    astropy memory-maps the whole file (every loop's images, 9.1 GB for a full-size
    ``est-mcao-solar`` export) though only the loop read is copied into memory; under
    an address-space limit (``ulimit -v``) the mapping failed with ``ENOMEM``, said as
    "does not fit in the memory" (issue 27, left12-export).
    """
    from modalinfo.common import memory

    size = path.stat().st_size
    left = memory.address_space_left_bytes()
    if size > left:
        raise LogFormatError(
            f"AOT file {quoted(path)} ({format_size(size)}) is memory-mapped whole to be read "
            f"and this process's address-space limit (ulimit -v) leaves "
            f"{format_size(left)}: raise the limit (mapped pages are read on demand, not "
            "held), or write the file without mode images (closedloop export "
            "--no-mode-images)")


#: peak bytes of :func:`modalinfo.bases.identify.identify_zernike` per byte of its
#: arrays: the cropped images 3 times (native copy, square crop, finite copy), the
#: ``(pixels, M)`` matrix and the ``(pixels, K)`` Zernike matrix twice each (fitted to
#: tracemalloc's 45.5 MB peak on est-mcao@16's ground mirror: 181 modes, 3,228 pixels,
#: 378 Zernikes; 46.7 MB by this rule)
_IMAGE_COPIES, _MATRIX_COPIES = 3.0, 2.0


def _reading_bytes(system, lp) -> tuple[float, str]:
    """Estimate the memory :func:`read_aot` holds for loop ``lp``, and what drives it.

    Nothing is read: the shapes come from the file's headers (memory-mapped arrays).

    Returns
    -------
    bytes : float
        Peak bytes: the coefficients (two float64 copies), or the measurements and
        reconstructor they are recomputed from, and the identification of the loop's
        mode images inside the mask's bounding box.
    what : str
        The arrays behind it, for a message.
    """
    from modalinfo.bases.identify import _candidates

    coeffs = _raw(lp.modal_coefficients)
    if coeffs is not None and coeffs.ndim == 2:
        n_frames, n_modes = coeffs.shape
        need = 2.0 * 8.0 * coeffs.size
        what = [f"coefficients {n_frames} x {n_modes}"]
    else:
        meas = _raw(getattr(lp.input_sensor, "measurements", None))
        rec = _raw(lp.measurements_to_modes)
        if meas is None or rec is None or meas.ndim < 1 or rec.ndim < 1:
            return 0.0, "nothing"
        n_frames, n_modes = meas.shape[0], rec.shape[0]
        need = 8.0 * (meas.size + rec.size + 2 * n_frames * n_modes)
        what = [f"measurements {meas.shape} and reconstructor {rec.shape}"]
    modes = _raw(lp.modes)
    if modes is not None and modes.ndim == 3 and modes.shape[0] == n_modes:
        mask = _pupil_mask(lp, system, modes)
        if mask is not None:
            rows, cols = _box(mask)
            box = (rows.stop - rows.start) * (cols.stop - cols.start)
            pixels = int(mask.sum())
        else:
            box = pixels = modes.shape[1] * modes.shape[2]
        n_cands = _candidates(n_modes, None).size
        need += 8.0 * (_IMAGE_COPIES * n_modes * box
                       + _MATRIX_COPIES * pixels * (n_modes + n_cands))
        what.append(f"the identification of {n_modes} mode images on {pixels} pupil pixels "
                    f"against {n_cands} Zernikes")
    return need, " and ".join(what)


def _check_reading(system, lp, path: Path) -> None:
    """Refuse loop ``lp`` if ``_reading_bytes`` exceeds the memory available."""
    from modalinfo.common import memory

    need, what = _reading_bytes(system, lp)
    avail = memory.usable_memory_bytes()
    if need > avail:
        raise LogFormatError(
            f"reading loop {lp.uid!r} of AOT file {quoted(path)} needs about {format_size(need)} "
            f"of memory ({what}), more than the {format_size(avail)} available; free "
            "memory or read a loop with fewer modes")


def _control_loops(system, path: Path) -> list:
    aotpy = import_aotpy()
    loops = [lp for lp in system.loops if isinstance(lp, aotpy.ControlLoop)]
    if not loops:
        raise LogFormatError(f"AOT file {quoted(path)} has no control loop")
    return loops


def aot_loops(path) -> list[str]:
    """Return the uids of the control loops of an AOT file, in file order."""
    path = as_path(path)
    return [lp.uid for lp in _control_loops(read_aot_system(path), path)]


def _check_loop(loop) -> None:
    if loop is not None and not isinstance(loop, str):
        raise TypeError(f"`loop` must be a str (a loop uid); got {type(loop).__name__}.")


def _pick_loop(system, path: Path, loop: str | None):
    loops = _control_loops(system, path)
    uids = ", ".join(repr(lp.uid) for lp in loops)
    if loop is None:
        usable = [lp for lp in loops if _has_coefficients(lp)]
        if len(usable) == 1:
            return usable[0], loops
        if len(loops) == 1:
            return loops[0], loops
        raise LogFormatError(
            f"AOT file {quoted(path)} has {len(loops)} control loops ({uids}); choose one with "
            "loop=UID (command line: --loop UID)"
        )
    for lp in loops:
        if lp.uid == loop:
            return lp, loops
    raise LogFormatError(f"AOT file {quoted(path)} has no control loop {loop!r}; its loops: {uids}")


def _raw(image) -> np.ndarray | None:
    """Return the image's array as the file holds it (memory-mapped, big-endian: nothing read)."""
    if image is None or getattr(image, "data", None) is None:
        return None
    return image.data if isinstance(image.data, np.ndarray) else np.asarray(image.data)


def _box(mask: np.ndarray) -> tuple[slice, slice]:
    """Rows and columns of ``mask``'s bounding box (``mask`` has a True pixel)."""
    rows = np.flatnonzero(mask.any(axis=1))
    cols = np.flatnonzero(mask.any(axis=0))
    return slice(int(rows[0]), int(rows[-1]) + 1), slice(int(cols[0]), int(cols[-1]) + 1)


def _data(image) -> np.ndarray | None:
    raw = _raw(image)
    return None if raw is None else _data_of(raw)


def _data_of(raw: np.ndarray) -> np.ndarray:
    """Return a native-byte-order contiguous copy (or view) of a file's array, values kept."""
    arr = np.asarray(raw)
    if not arr.dtype.isnative:
        arr = arr.astype(arr.dtype.newbyteorder("="))  # FITS is big-endian; values kept
    return np.ascontiguousarray(arr)


def _has_coefficients(lp) -> bool:
    return lp.modal_coefficients is not None or (
        lp.measurements_to_modes is not None and lp.input_sensor is not None
        and lp.input_sensor.measurements is not None
    )


def _number(value) -> float | None:
    if value is None:
        return None
    try:
        v = float(value)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def _int(value) -> int | None:
    v = _number(value)
    return None if v is None or v < 0 else int(v)


def _coefficients(lp, path: Path) -> tuple[np.ndarray, str]:
    if lp.modal_coefficients is not None:
        c = _data(lp.modal_coefficients)
        if c.ndim != 2 or c.dtype.kind not in "fiu":
            raise LogFormatError(
                f"AOT file {quoted(path)}: loop {lp.uid!r} modal_coefficients must be a numeric "
                f"(t, m) image; got {c.dtype} shape {c.shape}"
            )
        return c, "modal_coefficients"
    wfs = lp.input_sensor
    if lp.measurements_to_modes is None or wfs is None or wfs.measurements is None:
        raise LogFormatError(
            f"AOT file {quoted(path)}: loop {lp.uid!r} has neither modal_coefficients nor sensor "
            "measurements with measurements_to_modes"
        )
    meas = _data(wfs.measurements)
    rec = _data(lp.measurements_to_modes)
    t = meas.shape[0] if meas.ndim >= 1 else 0
    flat_m = meas.reshape(t, -1) if meas.ndim >= 2 else None
    flat_r = rec.reshape(rec.shape[0], -1) if rec.ndim >= 2 else None
    if flat_m is None or flat_r is None or flat_m.shape[1] != flat_r.shape[1]:
        raise LogFormatError(
            f"AOT file {quoted(path)}: loop {lp.uid!r} measurements {meas.shape} and "
            f"measurements_to_modes {rec.shape} do not match (need (t, d, s_v) and (m, d, s_v))"
        )
    coeffs = np.ascontiguousarray(flat_m.astype(np.float64) @ flat_r.astype(np.float64).T)
    return coeffs, (f"reconstructed: measurements_to_modes @ measurements of sensor "
                    f"{wfs.uid!r} (reference measurements not subtracted)")


def _times(lp, n_frames: int, path: Path) -> tuple[np.ndarray | None, list | None]:
    time = getattr(lp.modal_coefficients, "time", None) or lp.time
    if time is None and lp.modal_coefficients is None:  # reconstructed: the measurements'
        time = getattr(getattr(lp.input_sensor, "measurements", None), "time", None)
    if time is None:
        return None, None
    stamps = np.asarray(time.timestamps, dtype=np.float64)
    frames = list(time.frame_numbers) if time.frame_numbers else None
    if stamps.size == 0:
        return None, frames
    if stamps.shape != (n_frames,):
        raise LogFormatError(
            f"AOT file {quoted(path)}: loop {lp.uid!r} has {stamps.size} timestamps for "
            f"{n_frames} frames"
        )
    return stamps, frames


def _describe(system, lp, loops, path: Path) -> dict:
    """Describe the system as JSON-able metadata (numbers finite or absent)."""
    geom = geometry_of(system)
    meta: dict[str, Any] = {
        "source_file": path.name,
        "source_format": "aot",
        "aot_file": str(path.resolve()),
        "loop": "closed" if lp.closed else "open",
        "loop_uid": lp.uid,
        "loops": [x.uid for x in loops],
        "ao_mode": system.ao_mode,
    }
    # what the coefficients are (closedloop's MI_QUANT card: residual, pol, ...): a
    # pseudo-open-loop series of a closed loop is not that loop's residual
    cards = getattr(lp.modal_coefficients, "metadata", None) or []
    quantity = next((m.value for m in cards if getattr(m, "key", None) == "MI_QUANT"), None)
    if isinstance(quantity, str) and quantity:
        meta["coefficient_quantity"] = quantity
    # closedloop's MI_TRANS card: the frames before the loop's steady state, which the
    # quality pass leaves out as the closure transient (fix54-e); an integer >= 1 only
    transient = next((m.value for m in cards if getattr(m, "key", None) == "MI_TRANS"), None)
    if isinstance(transient, int) and not isinstance(transient, bool) and transient >= 1:
        meta["transient_frames"] = int(transient)
    meta.update(_closedloop_config(system))
    if system.name:
        meta["system"] = system.name
    if system.date_beginning is not None:
        meta["date"] = system.date_beginning.isoformat()
    tel = system.main_telescope
    if tel is not None:
        meta["telescope"] = tel.uid
        d = _number(tel.enclosing_diameter) or _number(tel.inscribed_diameter)
        if d is not None:
            meta["diameter"] = d
        obs = _number(tel.obstruction_diameter)
        if obs is not None:
            meta["obstruction_diameter"] = obs
    wfs = lp.input_sensor
    if wfs is not None:
        sensor = {"uid": wfs.uid, "type": type(wfs).__name__,
                  "n_valid_subapertures": _int(wfs.n_valid_subapertures),
                  "dimensions": _int(wfs.dimensions), "wavelength": _number(wfs.wavelength),
                  "source": getattr(wfs.source, "uid", None),
                  "source_type": type(wfs.source).__name__ if wfs.source is not None else None}
        sensor.update(geom.get("sensors", {}).get(wfs.uid, {}))
        meta["wfs"] = {k: v for k, v in sensor.items() if v is not None}
    cor = lp.commanded_corrector
    if cor is not None:
        corrector = {"uid": cor.uid, "type": type(cor).__name__,
                     "n_valid_actuators": _int(cor.n_valid_actuators)}
        corrector.update(geom.get("correctors", {}).get(cor.uid, {}))
        meta["corrector"] = {k: v for k, v in corrector.items() if v is not None}
    delay = _number(lp.delay)
    if delay is not None:
        meta["delay_frames"] = delay
    meta.update(_atmosphere_outer_scale(system))
    filt = {}
    for key, image in (("num", lp.time_filter_num), ("den", lp.time_filter_den)):
        arr = _data(image)
        if arr is not None and arr.size <= 4096 and np.all(np.isfinite(arr)):
            filt[key] = arr.astype(np.float64).tolist()
    if filt:
        meta["time_filter"] = filt
    return meta


def _closedloop_notes(system) -> dict | None:
    """Return closedloop's ``MI_CLOOP`` card of ``system`` as a dict, None for another writer."""
    card = next((m.value for m in getattr(system, "metadata", None) or []
                 if getattr(m, "key", None) == "MI_CLOOP"), None)
    try:
        notes = json.loads(card)
    except (TypeError, ValueError):
        return None
    if not isinstance(notes, dict) or notes.get("written_by") != "closedloop":
        return None
    return notes


def _closedloop_config(system) -> dict:
    """Return the run's config of a ``closedloop export`` file as metadata, else ``{}``.

    ``closedloop export`` writes the run's config as TOML in the system's ``config``
    (``aotpy``: ``AOSystem.config``, from ``SimulationConfig.to_dict``, the dict run.h5
    keeps as JSON). Read back as ``{"source": "closedloop", "config": dict}``, the keys a
    run.h5 log carries (``SimulationResult.from_run``), so that a forecaster fitted on
    the export knows the run's conditions (``closedloop.control.predictors.
    fitted_conditions``): without them it ran at another r0 without a word (round 55
    PART b, X48). Another writer's file, or a config that is not a TOML table of JSON
    values (no NaN or infinity: ``to_dict`` leaves an infinite outer scale out), gives
    ``{}``: the conditions are then unknown, as before.
    """
    if _closedloop_notes(system) is None:
        return {}
    text = config_of(system)
    if not isinstance(text, str):
        return {}
    import tomllib  # here: only a closedloop export needs it (the CLIs' start-up address space)

    try:
        config = tomllib.loads(text)
        config = json.loads(json.dumps(config, allow_nan=False))
    except (TypeError, ValueError):  # TOMLDecodeError is a ValueError
        return {}
    if not config:
        return {}
    return {"source": "closedloop", "config": config}


def _atmosphere_outer_scale(system) -> dict:
    """Return the first atmosphere's layers' outer scale as metadata (round 43 PART b, c51).

    One value shared by every layer: ``{"outer_scale": L0}`` (None when infinite, the
    metadata's word for Kolmogorov). Layers of different outer scales:
    ``{"atmosphere_layers": [{"outer_scale", "cn2_weight"}, ...]}``, which the theoretical
    K-L reads with the rule of a closedloop config's layers (their Cn2-weighted mean, a
    note). Nothing without one positive ``LAYERS_L0`` row (or one constant in time).
    """
    atmospheres = getattr(system, "atmosphere_params", None) or []
    if not atmospheres:
        return {}
    atm = atmospheres[0]
    l0 = _data(getattr(atm, "layers_l0", None))
    if l0 is None or l0.size == 0:
        return {}
    l0 = np.asarray(l0, dtype=np.float64).reshape(-1, l0.shape[-1])
    if not np.all(l0 == l0[:1]) or np.any(np.isnan(l0)) or np.any(l0 <= 0):
        return {}  # changing in time or not outer scales: nothing single to record
    scales = [None if math.isinf(v) else float(v) for v in l0[0]]
    if len(set(scales)) == 1:
        return {"outer_scale": scales[0]}
    w = _data(getattr(atm, "layers_relative_weight", None))
    w = None if w is None else np.asarray(w, dtype=np.float64).reshape(-1, w.shape[-1])
    if w is None or w.shape[-1] != len(scales) or not np.all(np.isfinite(w[0])) \
            or np.any(w[0] < 0) or not w[0].sum() > 0:
        return {}
    return {"atmosphere_layers": [{"outer_scale": s, "cn2_weight": float(x)}
                                  for s, x in zip(scales, w[0], strict=True)]}


def _card_wavelength(lp) -> float | None:
    """Return the coefficient image's ``MI_WAVEL`` card [m] (closedloop's export), or None.

    A value outside the log's wavelength range is ignored (not a wavelength in metres).
    """
    cards = getattr(lp.modal_coefficients, "metadata", None) or []
    raw = next((m.value for m in cards if getattr(m, "key", None) == _WAVELENGTH_KEY), None)
    value = _number(raw)
    low, high = WAVELENGTH_RANGE
    return value if value is not None and low <= value <= high else None


def _card_units(lp) -> str | None:
    """Return the coefficient image's ``MI_UNITS`` card (:func:`write_aot`'s), or None."""
    cards = getattr(lp.modal_coefficients, "metadata", None) or []
    raw = next((m.value for m in cards if getattr(m, "key", None) == _UNITS_KEY), None)
    return raw if isinstance(raw, str) else None


def _card_labels(lp, n_cols: int | None, path: Path) -> list[str] | None:
    """Return the labels of the coefficient image's ``MI_MODES`` card, or None (no card).

    Refuses (``LogFormatError``) a card that is not a JSON list of ``n_cols`` distinct
    non-empty strings (``n_cols`` None: the count is not checked).
    """
    cards = getattr(lp.modal_coefficients, "metadata", None) or []
    raw = next((m.value for m in cards if getattr(m, "key", None) == _LABELS_KEY), None)
    if raw is None:
        return None
    try:
        labels = json.loads(str(raw))
    except ValueError:
        labels = None
    if not (isinstance(labels, list) and all(isinstance(x, str) and x for x in labels)
            and len(set(labels)) == len(labels)
            and (n_cols is None or len(labels) == n_cols)):
        raise LogFormatError(
            f"AOT file {quoted(path)}: loop {lp.uid!r} card {_LABELS_KEY} must be a JSON list of "
            f"{n_cols if n_cols is not None else 'the'} distinct mode labels; got "
            f"{str(raw)[:60]!r}")
    return labels


def _identify(lp, system, n_cols: int, path: Path):
    """Identification of the loop's modes, or None; checks the mode count.

    Only the pixels inside the mask's bounding box are read into memory: the file's
    images span the mirror's whole plane (8.7x the disc's box on est-mcao-solar's
    ground mirror, 3.3 GB of mapped images), and the identification reads no pixel
    outside the mask (issue 27, left12-export).
    """
    raw = _raw(lp.modes)
    if raw is None:
        return None
    if raw.ndim != 3:
        raise LogFormatError(
            f"AOT file {quoted(path)}: loop {lp.uid!r} modes must be (m, h, w) images; got shape "
            f"{raw.shape}"
        )
    if raw.shape[0] != n_cols:
        raise LogFormatError(
            f"AOT file {quoted(path)}: loop {lp.uid!r} has {raw.shape[0]} modes but its "
            f"coefficients have {n_cols} columns"
        )
    from modalinfo.bases.identify import identify_zernike

    mask = _pupil_mask(lp, system, raw)
    if mask is None:  # the images' own support: every pixel is read
        return identify_zernike(_data_of(raw))
    rows, cols = _box(mask)
    return identify_zernike(_data_of(raw[:, rows, cols]), mask=mask[rows, cols])


def _pupil_mask(lp, system, modes: np.ndarray) -> np.ndarray | None:
    """Return the corrector's or telescope's pupil mask if it has the modes' shape, else None.

    ``modes`` may be the file's mapped array: only its shape is read.
    """
    for owner in (lp.commanded_corrector, system.main_telescope):
        mask = _data(getattr(owner, "pupil_mask", None))
        if mask is not None and mask.shape == modes.shape[1:] and mask.any():
            return mask != 0
    return None


@unwrap
def read_aot(path, *, loop: str | None = None, verify: bool = True, **hints) -> ModalLog:
    """Read one control loop of an AOT file as a ``ModalLog``.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    loop : str, optional
        uid of the control loop; needed when the file has several.
    verify : bool
        Verify FITS checksums where the file has them.
    **hints
        ``rate``, ``timestamps``, ``modes``, ``convention``, ``units``, ``wavelength``,
        ``metadata``, ``nonfinite``, ``start_time``: fill what the file lacks; a hint
        contradicting the file raises ``ValueError``.

    Returns
    -------
    ModalLog
        The loop's coefficients with time axis, units, modes and the system's
        description in ``metadata``.

    Raises
    ------
    LogFormatError
        Truncated or invalid AOT, no control loop, an unknown ``loop`` (the message
        lists the uids), several loops and no ``loop``, modes whose count differs
        from the coefficients' columns, timestamps of another length.
    """
    path = as_path(path)
    _check_loop(loop)
    system, notes = _read_system(path, verify)
    with reading("AOT", path):
        lp, loops = _pick_loop(system, path, loop)
        _check_reading(system, lp, path)
        _refuse_block(system, lp, path)
        coeffs, origin = _coefficients(lp, path)
        stamps, frames = _times(lp, coeffs.shape[0], path)
        ident = _identify(lp, system, coeffs.shape[1], path)
        own = _own_header(lp, path)
        if own is not None:
            stored = stored_from_header(own)
            if own["has_timestamps"]:
                stored["timestamps"] = stamps
            if list(coeffs.shape) != own["shape"] or coeffs.dtype.name != own["dtype"]:
                raise LogFormatError(
                    f"corrupt AOT file {quoted(path)}: coefficients {coeffs.shape} {coeffs.dtype} "
                    f"disagree with the header {tuple(own['shape'])} {own['dtype']}"
                )
        else:
            stored = _stored_from_system(system, lp, loops, path, coeffs, origin, stamps,
                                         frames, ident, hints.get("units"),
                                         modes_hint="modes" in hints)
            coeffs = stored.pop("_coeffs")
            if notes:  # aotpy's verification remarks on a foreign file, kept, not hidden
                stored["metadata"]["aot_warnings"] = list(dict.fromkeys(notes))[:10]
    # an AOT file another program wrote supplies its own frame times (Leftovers 26-rate)
    return build_log(coeffs, path, stored, hints, own_times=own is not None)


def _no_images_reason(system) -> str:
    """Return why a ``closedloop export`` file has no mode images ("" for another writer).

    ``closedloop export --no-mode-images`` leaves them out (they are most of the file);
    ``reorder --basis file`` on such a file said "has no mode images" without naming the
    option (adversarial round 54 PART b, P23). The ``MI_CLOOP`` card says
    ``mode_images: false`` since fix55-c; an older export of closedloop has none either
    way, so the option is named as the likely cause.
    """
    notes = _closedloop_notes(system)
    if notes is None:
        return ""
    again = ("; export the result again without that option (closedloop export RUN.h5 "
             "OUT.fits) to read the mirror's basis")
    if notes.get("mode_images") is False:
        return ("; the file was written by `closedloop export --no-mode-images` (Python: "
                f"mode_images=False), which leaves them out{again}")
    if "mode_images" not in notes:
        return ("; the file was written by `closedloop export`, whose option "
                f"--no-mode-images (Python: mode_images=False) leaves them out{again}")
    return ""


def _refuse_block(system, lp, path: Path) -> None:
    """Refuse a loop that closedloop's ``MI_CLOOP`` card calls a block, no coefficients.

    ``closedloop export`` writes each block of a global reconstructor (``dm0.wfs1``:
    one sensor's share of a mirror's modes) as a loop without coefficients; read
    through ``measurements_to_modes @ measurements`` it was presented as a log of
    ``dm0`` (adversarial round 25 PART b, A4, A6). The loops with coefficients are named.
    """
    if lp.modal_coefficients is not None:
        return
    card = next((m.value for m in getattr(system, "metadata", None) or []
                 if getattr(m, "key", None) == "MI_CLOOP"), None)
    try:
        described = json.loads(card)["loops"]
        said = described[lp.uid]
    except (TypeError, ValueError, KeyError):
        return
    if isinstance(said, str) and "no coefficients" in said:
        logs = [uid for uid, text in described.items()
                if not (isinstance(text, str) and "no coefficients" in text)]
        raise LogFormatError(
            f"AOT file {quoted(path)}: loop {lp.uid!r} holds no coefficients (the file's MI_CLOOP "
            f"card: {said!r}); its logs are the loops {', '.join(map(repr, logs))}: pick "
            "one with loop= (command line: --loop UID)")


def _own_header(lp, path: Path) -> dict | None:
    image = lp.modal_coefficients
    if image is None:
        return None
    for md in image.metadata:
        if md.key == _JSON_KEY:
            return parse_header(str(md.value), "AOT", path)
    return None


def _stored_from_system(system, lp, loops, path, coeffs, origin, stamps, frames, ident,
                        units_hint: str | None = None, modes_hint: bool = False) -> dict:
    meta = _describe(system, lp, loops, path)
    meta["coefficients"] = origin
    stored: dict[str, Any] = {"metadata": meta, "timestamps": stamps}
    unit = getattr(lp.modal_coefficients, "unit", None)
    if not (isinstance(unit, str) and unit.strip()):
        # no BUNIT: write_aot's MI_UNITS card (a log in waves), read as BUNIT is
        unit = _card_units(lp)
    if isinstance(unit, str) and unit.strip():
        meta["aot_unit"] = unit.strip()
        known = unit_word(unit)
        if known is None and units_hint is None:
            raise LogFormatError(
                f"AOT file {quoted(path)}: loop {lp.uid!r} coefficient unit {unit.strip()!r} is "
                "not "
                "a unit of phase (rad, waves) or optical path (m, nm, um); state the units "
                "with units= (command line: --in-units) if the card is wrong"
            )
        if known is not None:  # a contradicting units= hint is refused by build_log
            stored["units"], scale = known
            if scale != 1.0:
                coeffs = coeffs.astype(np.float64) * scale
                meta["unit_conversion"] = (f"coefficients in {unit.strip()} in the file, "
                                           f"converted to {stored['units']}")
    elif units_hint is None:
        # the file does not say: rad is the default, and it is an assumption (README
        # "Foreign logs"), so `info` marks it and `convert --units` refuses to convert
        meta["assumed"] = {"units": "rad"}
    wavelength = _card_wavelength(lp)
    if wavelength is not None and stored.get("units", "rad") in ("rad", "waves"):
        # closedloop's export: the phase's wavelength (card MI_WAVEL) kept on the round trip
        stored["wavelength"] = wavelength
    rate = _number(lp.framerate)
    if rate is not None and rate > 0:
        if stamps is not None and stamps.size > 1:
            # the one agreement rule (median or mean regular interval: audit 10-time);
            # timestamps that are not increasing are refused by the log, naming the file
            try:
                agrees = rate_agrees(stamps, rate)
            except ValueError:
                agrees = False
            if agrees:
                stored["rate"] = rate
            else:
                dt = float(np.median(np.diff(stamps)))
                meta["framerate"] = rate  # disagrees with the timestamps: kept apart
                # and said: a 2x contradiction went unremarked (round 10 PART b, row A04)
                meta["framerate_note"] = (
                    f"the loop's FRAMERATE card ({rate:.6g} Hz) disagrees with its "
                    f"timestamps ({1.0 / dt:.6g} Hz median); the timestamps are used"
                    if dt > 0 else f"the loop's FRAMERATE card ({rate:.6g} Hz) disagrees "
                    "with its timestamps, which are used")
        else:
            stored["rate"] = rate
    if frames:
        meta["frame_numbers"] = [_number(frames[0]), _number(frames[-1])]
    labels = _card_labels(lp, coeffs.shape[1], path)
    if ident is None and labels is None:
        meta["modes_note"] = ("the loop has no mode images: the column labels are the default "
                              "(Noll 2..m+1) unless given")
        if not modes_hint and coeffs.shape[1]:  # (no modes: refused by the log, naming it)
            # assumed, as the units are: `info` marks it, the commands note it (README
            # "Foreign logs"; adversarial round 10 PART b, rows A01, A02)
            from modalinfo.io._foreign import describe_modes
            from modalinfo.telemetry.checks import default_modes

            meta["assumed"] = {**meta.get("assumed", {}), "modes": describe_modes(
                default_modes("noll", coeffs.shape[1]), "noll")}
    elif (ident is not None and ident.all_zernike and bool(np.all(ident.sign > 0))
          and labels is None):  # the file's own names win (read_aot_basis's rule)
        meta["modes_identification"] = ident.to_dict()
        stored["modes"] = [int(j) for j in ident.noll]
        stored["convention"] = "noll"
    else:
        if ident is not None:
            meta["modes_identification"] = ident.to_dict()
        # the file's own labels (MI_MODES) name modes that are not Zernikes
        stored["modes"] = labels or [f"mode{k + 1}" for k in range(coeffs.shape[1])]
        stored["convention"] = "labels"
    stored["_coeffs"] = coeffs
    return stored


def read_aot_basis(path, *, loop: str | None = None, verify: bool = True):
    """Return the modal basis a loop of an AOT file carries, on the file's pupil.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    loop : str, optional
        uid of the control loop (needed when the file has several).
    verify : bool
        Verify FITS checksums where the file has them.

    Returns
    -------
    basis : ModalBasis
        Columns: the loop's mode images on the pupil (the corrector's or telescope's
        pupil mask when it has the images' shape, else the images' support); labels
        ``"Z<j>"`` for modes identified as positive Zernikes, else ``"mode<k>"``; the
        ``MI_MODES`` card's labels when the modes are not all positive Zernikes.
    identification : ZernikeIdentification
        Which Zernike each mode is (our convention).

    Raises
    ------
    LogFormatError
        No such loop, or a loop without ``modes``.
    """
    from modalinfo.bases.image_basis import basis_from_images

    path = as_path(path)
    _check_loop(loop)
    system = read_aot_system(path, verify=verify)
    with reading("AOT", path):
        lp, _ = _pick_loop(system, path, loop)
        raw = _raw(lp.modes)
        if raw is None:
            # its coefficients may have labels (MI_MODES, e.g. DMKL1...): "no modes" read
            # as a contradiction of `modalinfo info` (adversarial round 8, row e122)
            raise LogFormatError(
                f"AOT file {quoted(path)}: loop {lp.uid!r} has no mode images (no `modes` "
                f"data), so no modal basis can be read from it{_no_images_reason(system)}")
        _check_reading(system, lp, path)
        n_cols = None
        if _has_coefficients(lp):
            n_cols = _coefficients(lp, path)[0].shape[1]
        ident = _identify(lp, system, raw.shape[0] if n_cols is None else n_cols, path)
        # only the mask's bounding box is copied out of the mapped file (the basis reads
        # no pixel outside the mask; issue 27, left12-export)
        mask = _pupil_mask(lp, system, raw)
        if mask is None:
            modes = _data_of(raw)
        else:
            rows, cols = _box(mask)
            modes, mask = _data_of(raw[:, rows, cols]), mask[rows, cols]
        tel = system.main_telescope
        d = (_number(tel.enclosing_diameter) if tel is not None else None) or 1.0
        labels = [f"Z{int(j)}" if ok and s > 0 else f"mode{k + 1}"
                  for k, (j, ok, s) in enumerate(zip(ident.noll, ident.is_zernike, ident.sign,
                                                     strict=True))]
        named = _card_labels(lp, n_cols, path) if n_cols is not None else None
        if named is not None:
            # the file's own names of modes that are not Zernikes, also where images pass
            # the 0.95 correlation rule: K-L modes KL1..KL10 of Z2..Z11 were read back as
            # Z2, Z3, Z4 (KL3 = 0.984 Z4 - 0.178 Z11; audit 10, feedback, row aotb-kl)
            labels = named
        elif len(set(labels)) != len(labels):
            labels = [f"mode{k + 1}" for k in range(len(labels))]
        basis = basis_from_images(modes, mask=mask, diameter=d, labels=labels)
    return basis, ident


def write_system(system, path, *, overwrite: bool = False) -> Path:
    """Write an ``aotpy.AOSystem`` to an AOT FITS file, atomically, with checksums.

    Parameters
    ----------
    system : aotpy.AOSystem
        The system (e.g. from :func:`modalinfo.io.aot_system.build_system`).
    path : str or os.PathLike
        Target file.
    overwrite : bool
        Replace an existing file; otherwise ``FileExistsError``.

    Returns
    -------
    pathlib.Path
        The written path.
    """
    path = as_path(path)
    found = _non_ascii_text(system)
    if found is not None:
        # a config named 'KAOS – Télescope' failed in astropy ("FITS header values must
        # contain standard printable ASCII characters") naming no field (round 21 PART b,
        # c23); a log's telescope metadata was named by its value only (u04)
        where, text = found
        raise ValueError(
            f"an AOT file's text is ASCII (FITS tables and headers); {where} = {text!r} is "
            "not: rename it (a log's metadata / labels, a closedloop config's name), or "
            "write npz / hdf5 / csv, which keep it")

    def write(name: Path) -> None:
        with catching_warnings():
            # aotpy notes empty optional tables as warnings; the file is valid AOT
            warnings.filterwarnings("ignore", message=r".*contains no data.*")
            from aotpy.io.fits.writer import AOTFITSWriter

            from modalinfo.io.fits import write_hdulist

            # aotpy's writer's HDUs, written with checksums that hold no clock time
            try:
                write_hdulist(AOTFITSWriter(system).get_hdulist(), os.fspath(name))
            except UnicodeEncodeError as exc:
                # FITS tables hold ASCII text: a telescope named 'Téide' failed as "'ascii'
                # codec can't encode character" naming neither the text nor the way out
                # (round 19 PART b, C2)
                text = str(exc.object) if isinstance(exc.object, str) else repr(exc.object)
                raise ValueError(
                    f"an AOT file's text is ASCII (FITS tables); {text!r}, a name or "
                    "metadata value of the log, is not: rename it, or write npz / hdf5 / "
                    "csv, which keep it") from None

    return atomic_write(path, write, overwrite=overwrite, by_name=True)


def _non_ascii_text(obj, where: str = "system", seen: set | None = None,
                    depth: int = 0) -> tuple[str, str] | None:
    """Return ``(field path, text)`` of the first non-ASCII str in an AOT object, or None."""
    if isinstance(obj, str):
        return None if obj.isascii() else (where, obj)
    if depth > 8 or obj is None or isinstance(obj, (int, float, bytes, np.ndarray, np.generic)):
        return None
    seen = set() if seen is None else seen
    if id(obj) in seen:
        return None
    seen.add(id(obj))
    if isinstance(obj, dict):
        items = ((f"{where}[{k!r}]", v) for k, v in obj.items())
    elif isinstance(obj, (list, tuple)):
        items = ((f"{where}[{k}]", v) for k, v in enumerate(obj))
    elif hasattr(obj, "__dict__"):
        items = ((f"{where}.{k}", v) for k, v in vars(obj).items() if not k.startswith("_"))
    else:
        return None
    for name, value in items:
        found = _non_ascii_text(value, name, seen, depth + 1)
        if found is not None:
            return found
    return None


def check_aot_size(path, file_bytes: float, memory_bytes: float, *, what: str,
                   fix: str = "", memory: float | None = None,
                   error: type[Exception] = MemoryError) -> None:
    """Refuse an AOT file that cannot fit in memory or on disk, before any byte is written.

    The one check behind :func:`write_aot` and closedloop's AOT export.

    Parameters
    ----------
    path : str or os.PathLike
        The target file (its folder's free space is checked).
    file_bytes, memory_bytes : float
        Estimated size of the file and peak memory of writing it [bytes].
    what : str
        The work, starting the memory message (``"writing this log as AOT"``).
    fix : str
        Appended to either message (``"; ... pass mode_images=False ..."``).
    memory : float, optional
        Memory the writer may use [bytes]; default
        :func:`modalinfo.common.memory.usable_memory_bytes` (available memory, capped by
        the address space an ``ulimit -v`` leaves).
    error : type
        Exception raised for memory (a ``MemoryError`` by default; closedloop passes its
        ``ResourceError``).

    Raises
    ------
    error
        One line: the memory needed, the limit and the file's size.
    modalinfo.common.folders.OutputError
        The folder lacks the file's size.
    """
    from modalinfo.common import memory as _memory
    from modalinfo.common.folders import OutputError, check_room

    path = as_path(path)
    limit = _memory.usable_memory_bytes() if memory is None else float(memory)
    if memory_bytes > limit:
        raise error(f"{what} needs about {format_size(memory_bytes)} of memory, more than "
                    f"the {format_size(limit)} available (the file is about "
                    f"{format_size(file_bytes)}{fix}).")
    try:
        check_room(Path(os.path.abspath(path)).parent, file_bytes, f"AOT file {quoted(path)}")
    except OutputError as exc:
        raise OutputError(f"{exc}{fix}") from None


def estimate_write_aot(log: ModalLog, basis=None) -> tuple[float, float]:
    """Estimate the file and the peak memory of ``write_aot(log, ..., basis=basis)``.

    Parameters
    ----------
    log : ModalLog
        The log (its shape and dtype; nothing is copied).
    basis : ModalBasis, optional
        Its mode images ``(M, n, n)`` float64 and pupil mask ``(n, n)`` int16 are counted.

    Returns
    -------
    file_bytes, memory_bytes : float
        [bytes]: the arrays, one header and padding per image and aotpy's tables; the
        memory is ``_WRITE_COPIES`` copies of the arrays (the interpreter not counted).
    """
    coeffs = np.asarray(log.coeffs)
    arrays = float(coeffs.nbytes)
    hdus = 1
    if log.timestamps is not None:
        arrays += 8.0 * np.shape(log.timestamps)[0]
        hdus += 1
    if basis is not None:
        n_rows, n_cols = np.shape(basis.pupil.mask)
        arrays += 8.0 * basis.n_modes * n_rows * n_cols + 2.0 * n_rows * n_cols
        hdus += 2
    file_bytes = arrays + TABLE_BYTES + HDU_OVERHEAD * hdus
    return file_bytes, _WRITE_COPIES * arrays


def write_aot(log: ModalLog, path, *, overwrite: bool = False, basis=None,
              loop: str = "loop") -> Path:
    """Write ``log`` as a minimal valid AOT system (one control loop), atomically.

    The system holds a telescope (diameter from ``metadata["diameter"]`` or the
    basis's pupil), a natural source, a Shack-Hartmann sensor and a deformable
    mirror (their counts from the log's AOT metadata when present, else 0: unknown),
    and the loop: ``modal_coefficients`` (the log's dtype), ``Time`` timestamps when
    the log has them, ``framerate``, delay, and the log's JSON header as the card
    ``MI_JSON`` so that :func:`read_aot` gives the log back exactly.

    Parameters
    ----------
    log : ModalLog
        The log.
    path : str or os.PathLike
        Target file.
    overwrite : bool
        Replace an existing file; otherwise ``FileExistsError``.
    basis : ModalBasis, optional
        Also write its modes as the loop's ``modes`` images (0 outside the pupil) and
        its pupil as the telescope's pupil mask; ``basis.n_modes`` must equal
        ``log.n_modes``.
    loop : str
        uid of the loop.

    Returns
    -------
    pathlib.Path
        The written path.

    Raises
    ------
    MemoryError
        Writing would need more memory than available (``estimate_write_aot``,
        ``check_aot_size``), checked before any byte is written.
    modalinfo.common.folders.OutputError
        The target's folder has less free space than the file needs.
    """
    if not isinstance(log, ModalLog):
        raise TypeError(f"`log` must be a ModalLog; got {type(log).__name__}.")
    path = as_path(path)
    meta = log.metadata
    wfs_meta = meta.get("wfs") if isinstance(meta.get("wfs"), dict) else {}
    cor_meta = meta.get("corrector") if isinstance(meta.get("corrector"), dict) else {}
    modes = pupil_mask = None
    diameter = _number(meta.get("diameter"))
    extra_cards: dict = {}
    if basis is not None:
        if not hasattr(basis, "matrix") or not hasattr(basis, "pupil"):
            raise TypeError(f"`basis` must be a ModalBasis; got {type(basis).__name__}.")
        if basis.n_modes != log.n_modes:
            raise ValueError(f"`basis` has {basis.n_modes} modes but the log has {log.n_modes} "
                             "columns; they must match.")
    # before the mode images are made and any byte is written (left13-cli)
    file_bytes, memory_bytes = estimate_write_aot(log, basis)
    check_aot_size(path, file_bytes, memory_bytes, what="writing this log as AOT")
    if basis is not None:
        modes = np.nan_to_num(basis.pupil.to_image(np.asarray(basis.matrix).T), nan=0.0)
        names = [str(s) for s in basis.labels]
        if not all(re.fullmatch(r"Z[1-9][0-9]*", s) for s in names):
            # modes that are not Noll Zernikes (K-L...): their names, as closedloop's export
            extra_cards[_LABELS_KEY] = json.dumps(names, separators=(",", ":"))
        pupil_mask = basis.pupil.mask
        diameter = diameter if diameter is not None else float(basis.pupil.diameter)
    # BUNIT only for a unit FITS 4.0 section 4.3 spells (rad, nm, um): BUNIT = 'waves'
    # was not one (astropy.units.Unit refuses it); MI_UNITS names the units of every log
    # (stop 56's left item: fix49-c's rule for FITS files, here for AOT; fix50-b)
    units = log.units if log.units in FITS_UNITS else None
    extra_cards[_UNITS_KEY] = log.units
    header = dumps(log_header(log, checksum=False))
    spec = LoopSpec(
        uid=str(loop), sensor=str(wfs_meta.get("uid", "wfs")),
        corrector=str(cor_meta.get("uid", "dm")),
        modal_coefficients=np.ascontiguousarray(log.coeffs), units=units,
        timestamps=None if log.timestamps is None else np.asarray(log.timestamps),
        framerate=log._rate,  # noqa: SLF001 - the nominal rate as given (None if none)
        delay=_number(meta.get("delay_frames")),
        modes=modes, closed=meta.get("loop") != "open",
        coefficient_metadata={_JSON_KEY: header, **extra_cards},
    )
    system = build_system(
        [spec],
        sensors=[SensorSpec(uid=spec.sensor, source="source",
                            n_valid_subapertures=_int(wfs_meta.get("n_valid_subapertures")) or 0)],
        correctors=[CorrectorSpec(uid=spec.corrector,
                                  n_valid_actuators=_int(cor_meta.get("n_valid_actuators")) or 0)],
        telescope=TelescopeSpec(uid=str(meta.get("telescope", "telescope")) or "telescope",
                                diameter=diameter, pupil_mask=pupil_mask),
        name=meta.get("system") if isinstance(meta.get("system"), str) else None,
        config=json.dumps({"written_by": "modalinfo", "n_valid_counts": "0 means unknown"}),
    )
    return write_system(system, path, overwrite=overwrite)
