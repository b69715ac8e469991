"""Build an AOT system (``aotpy.AOSystem``) from plain descriptions of its parts.

The writer of ``modalinfo.io.aot`` uses it for one loop around a ``ModalLog``;
the closed-loop simulator uses it to export a complete run: the telescope, its
sources (the Sun is a ``"natural"`` guide source: AOT has no extended-source type),
each wavefront sensor with its measurements, each corrector, the atmosphere's layers
and each control loop with its modal coefficients, modes, reconstructor, time filter
and delay. Every description is a small frozen dataclass holding numbers and arrays;
objects refer to each other by ``uid``.

AOT has no field for a corrector's conjugation altitude nor a sensor's field of
view: :func:`build_system` records them (and any ``extra`` of a part) as JSON in the
system keyword ``MI_GEOM``, which :func:`geometry_of` reads back. Arrays are passed to
``aotpy`` unchanged, so ``aotpy`` writes them with their dtype (float32 or float64)
and reading gives the same bits.

Time filter convention (AOT: "the first numerator is the loop gain"): numerator and
denominator coefficients in powers of ``z^-1``, one row per mode or one row for all;
an integrator ``u_k = (1 - leak) u_{k-1} + g e_k`` (``leak`` 0: pure integrator, as in the
simulator) is ``num = [[g]]``, ``den = [[1, -(1 - leak)]]`` (:func:`integrator_filter`,
read back by :func:`integrator_from_filter`).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = [
    "AOT_EXTRA_KEY",
    "AtmosphereSpec",
    "CorrectorSpec",
    "LoopSpec",
    "SensorSpec",
    "SourceSpec",
    "TelescopeSpec",
    "build_system",
    "config_of",
    "geometry_of",
    "import_aotpy",
    "integrator_filter",
    "integrator_from_filter",
]

#: Primary-header keyword holding what AOT has no field for (altitudes, fields, extras).
AOT_EXTRA_KEY = "MI_GEOM"


def import_aotpy():
    """Import ``aotpy`` or raise ``ImportError`` saying how to install it."""
    try:
        import aotpy
    except ImportError as exc:  # pragma: no cover - aotpy is a core dependency
        raise ImportError(
            "reading or writing AOT files needs the `aotpy` package, a dependency of "
            "modalinfo; reinstall with `pip install modalinfo` (or `pip install aotpy`)"
        ) from exc
    return aotpy


@dataclass(frozen=True)
class TelescopeSpec:
    """The main telescope.

    Attributes
    ----------
    uid : str
        Identifier.
    diameter : float or None
        Enclosing diameter [m].
    obscuration_diameter : float or None
        Central obstruction diameter [m].
    pupil_mask : numpy.ndarray or None
        ``(h, w)`` pupil, 1 inside (written as int).
    elevation, azimuth : float or None
        Pointing at start [deg].
    """

    uid: str = "telescope"
    diameter: float | None = None
    obscuration_diameter: float | None = None
    pupil_mask: np.ndarray | None = None
    elevation: float | None = None
    azimuth: float | None = None


@dataclass(frozen=True)
class SourceSpec:
    """A light source.

    Attributes
    ----------
    uid : str
        Identifier.
    kind : {"natural", "science"}
        AOT source type (the Sun, an extended source, is ``"natural"``).
    elevation_offset, azimuth_offset : float or None
        Offset from the telescope pointing [deg].
    fwhm : float or None
        Effective width [rad].
    extra : dict
        JSON-serialisable extras (e.g. ``{"extended": "sun"}``), kept in ``MI_GEOM``.
    """

    uid: str = "source"
    kind: str = "natural"
    elevation_offset: float | None = None
    azimuth_offset: float | None = None
    fwhm: float | None = None
    extra: dict = field(default_factory=dict)


@dataclass(frozen=True)
class SensorSpec:
    """A wavefront sensor (Shack-Hartmann or pyramid).

    Attributes
    ----------
    uid : str
        Identifier.
    source : str
        ``uid`` of its source.
    n_valid_subapertures : int
        Valid subapertures ``s_v`` (0 when unknown).
    kind : {"shack-hartmann", "pyramid"}
        Sensor type.
    measurements : numpy.ndarray or None
        ``(t, d, s_v)`` measurements (``d = 2`` for a Shack-Hartmann); their times
        are those of the first loop reading this sensor when the lengths agree.
    subaperture_mask : numpy.ndarray or None
        ``(s, s)`` int grid, ``-1`` outside, else the valid subaperture's index.
    wavelength : float or None
        Sensing wavelength [m].
    field_of_view : float or None
        Field the sensor averages over [arcsec] (kept in ``MI_GEOM``).
    altitude : float or None
        Conjugation altitude [m] (kept in ``MI_GEOM``).
    n_sides : int
        Pyramid sides (pyramid only).
    dimensions : int or None
        Values per subaperture ``d`` of a pyramid (default 4; a Shack-Hartmann has 2).
    units : str or None
        Units of the measurements (``BUNIT``; AOT: user defined).
    extra : dict
        JSON-serialisable extras, kept in ``MI_GEOM``.
    """

    uid: str
    source: str
    n_valid_subapertures: int = 0
    kind: str = "shack-hartmann"
    measurements: np.ndarray | None = None
    subaperture_mask: np.ndarray | None = None
    wavelength: float | None = None
    field_of_view: float | None = None
    altitude: float | None = None
    n_sides: int = 4
    dimensions: int | None = None
    units: str | None = None
    extra: dict = field(default_factory=dict)


@dataclass(frozen=True)
class CorrectorSpec:
    """A wavefront corrector (deformable or tip-tilt mirror).

    Attributes
    ----------
    uid : str
        Identifier.
    n_valid_actuators : int
        Valid actuators ``a_v`` (0 when unknown; 2 for a tip-tilt mirror).
    kind : {"dm", "tip-tilt"}
        Corrector type.
    altitude : float or None
        Conjugation altitude [m] (kept in ``MI_GEOM``).
    pupil_mask : numpy.ndarray or None
        ``(h, w)`` pupil or meta-pupil, 1 inside.
    influence_function : numpy.ndarray or None
        ``(a_v, h, w)`` influence functions [m] (DM only).
    extra : dict
        JSON-serialisable extras, kept in ``MI_GEOM``.
    """

    uid: str
    n_valid_actuators: int = 0
    kind: str = "dm"
    altitude: float | None = None
    pupil_mask: np.ndarray | None = None
    influence_function: np.ndarray | None = None
    extra: dict = field(default_factory=dict)


@dataclass(frozen=True)
class AtmosphereSpec:
    """Atmospheric parameters: one set of layers, constant over the recording.

    Attributes
    ----------
    uid : str
        Identifier.
    wavelength : float or None
        Reference wavelength of ``r0`` [m].
    r0 : float or None
        Fried parameter at zenith [m].
    heights, weights, wind_speeds, wind_directions, outer_scales : numpy.ndarray or None
        ``(l,)`` layer heights [m], fractions (sum 1), wind speeds [m/s], wind
        directions [deg, 0 = North, eastward] and outer scales [m]; written as
        ``(1, l)`` images.
    """

    uid: str = "atmosphere"
    wavelength: float | None = None
    r0: float | None = None
    heights: np.ndarray | None = None
    weights: np.ndarray | None = None
    wind_speeds: np.ndarray | None = None
    wind_directions: np.ndarray | None = None
    outer_scales: np.ndarray | None = None


@dataclass(frozen=True)
class LoopSpec:
    """A control loop: one sensor driving one corrector.

    Attributes
    ----------
    uid : str
        Identifier (what ``modalinfo.io.load(..., loop=uid)`` selects).
    sensor, corrector : str
        ``uid`` of the input sensor and the commanded corrector.
    modal_coefficients : numpy.ndarray or None
        ``(t, m)`` modal coefficients (float32 or float64, kept).
    units : str or None
        Units of the coefficients (``"rad"``, ``"nm"``, ``"um"``, ``"waves"``, ``"m"``).
    timestamps : numpy.ndarray or None
        ``(t,)`` times [s] of the frames (AOT: Unix time; relative times are kept as
        given).
    framerate : float or None
        Loop rate [Hz].
    delay : float or None
        Loop delay [frames], integration mid-point to command mid-point.
    modes : numpy.ndarray or None
        ``(m, h, w)`` mode images (0 outside the pupil). The same array object given to
        several loops is written once, as one image they all reference.
    measurements_to_modes : numpy.ndarray or None
        ``(m, d, s_v)`` reconstructor.
    modes_to_commands : numpy.ndarray or None
        ``(a_v, m)``.
    commands : numpy.ndarray or None
        ``(t, a_v)`` corrector commands (AOT: [m]).
    command_units : str
        Units written for ``commands`` (default ``"m"``, AOT's; a modal corrector whose
        "actuators" are modes may say e.g. ``"rad"``).
    time_filter_num, time_filter_den : numpy.ndarray or None
        ``(m or 1, i)`` and ``(m or 1, j)`` controller coefficients (powers of
        ``z^-1``; see :func:`integrator_filter`).
    closed : bool
        Loop closed during the recording.
    coefficient_metadata : dict
        Extra cards on the coefficient image: str keys of at most 8 upper-case
        characters, str/float/int values (the modalinfo writer stores its JSON header
        here as ``MI_JSON``).
    """

    uid: str
    sensor: str
    corrector: str
    modal_coefficients: np.ndarray | None = None
    units: str | None = None
    timestamps: np.ndarray | None = None
    framerate: float | None = None
    delay: float | None = None
    modes: np.ndarray | None = None
    measurements_to_modes: np.ndarray | None = None
    modes_to_commands: np.ndarray | None = None
    commands: np.ndarray | None = None
    command_units: str = "m"
    time_filter_num: np.ndarray | None = None
    time_filter_den: np.ndarray | None = None
    closed: bool = True
    coefficient_metadata: dict = field(default_factory=dict)


def integrator_filter(gain, leak: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """AOT time filter of a (leaky) integrator ``u_k = (1 - leak) u_{k-1} + gain e_k``.

    The AOT boundary for ``leak``: here, as in the simulator (``closedloop``'s
    ``LoopConfig.leak``), 0 is a pure integrator; the file's denominator holds what
    the standard defines, the factor ``1 - leak`` applied to the previous command.
    :func:`integrator_from_filter` reads it back.

    Parameters
    ----------
    gain : float or array_like
        Loop gain, one for all modes or ``(m,)`` per mode.
    leak : float
        Leak in [0, 1): the fraction of the previous command forgotten at each step
        (0: pure integrator).

    Returns
    -------
    num, den : numpy.ndarray
        ``(m, 1)`` numerators ``[[gain]]`` and ``(m, 2)`` denominators
        ``[[1, -(1 - leak)]]`` in powers of ``z^-1``.
    """
    g = np.atleast_1d(np.asarray(gain, dtype=np.float64))
    if g.ndim != 1:
        raise ValueError(f"`gain` must be a scalar or 1-D; got shape {g.shape}.")
    num = g[:, None].copy()
    den = np.tile(np.array([[1.0, -(1.0 - float(leak))]]), (g.size, 1))
    return num, den


def integrator_from_filter(num, den) -> tuple[np.ndarray, np.ndarray]:
    """Gain and leak of an AOT integrator time filter (the inverse of :func:`integrator_filter`).

    Parameters
    ----------
    num, den : array_like
        ``(m, 1)`` numerators and ``(m, 2)`` denominators ``[[1, -(1 - leak)]]`` in
        powers of ``z^-1`` (one row per mode, or one row for all).

    Returns
    -------
    gain, leak : numpy.ndarray
        ``(m,)`` each; ``leak`` 0 is a pure integrator.

    Raises
    ------
    ValueError
        A filter that is not an integrator (other shapes, or ``den[:, 0] != 1``).
    """
    num = np.atleast_2d(np.asarray(num, dtype=np.float64))
    den = np.atleast_2d(np.asarray(den, dtype=np.float64))
    if num.ndim != 2 or num.shape[1] != 1 or den.ndim != 2 or den.shape[1] != 2:
        raise ValueError(
            f"an integrator's time filter has num (m, 1) and den (m, 2); got "
            f"{num.shape} and {den.shape}."
        )
    if not np.all(den[:, 0] == 1.0):
        raise ValueError(f"`den` must start with 1 in every row; got {den[:, 0].tolist()}.")
    return num[:, 0].copy(), 1.0 + den[:, 1]


def _image(aotpy, name: str, data, *, unit=None, time=None, metadata=None):
    if data is None:
        return None
    cards = [aotpy.Metadatum(k, v) for k, v in (metadata or {}).items()]
    return aotpy.Image(name, np.asarray(data), unit=unit, time=time, metadata=cards)


def _by_uid(items, what: str) -> dict:
    out = {}
    for item in items:
        if item.uid in out:
            raise ValueError(f"two {what} share the uid {item.uid!r}; uids must be unique.")
        out[item.uid] = item
    return out


def build_system(
    loops,
    *,
    sensors,
    correctors,
    sources=(),
    telescope: TelescopeSpec | None = None,
    atmosphere=(),
    ao_mode: str | None = None,
    name: str | None = None,
    config: str | None = None,
    date_beginning=None,
):
    """Build an ``aotpy.AOSystem`` from descriptions of its parts.

    Parameters
    ----------
    loops : sequence of LoopSpec
        Control loops (at least one).
    sensors : sequence of SensorSpec
        Wavefront sensors.
    correctors : sequence of CorrectorSpec
        Wavefront correctors.
    sources : sequence of SourceSpec
        Sources (a default natural source is added when a sensor names ``"source"``
        and none is given).
    telescope : TelescopeSpec, optional
        The main telescope (default: ``TelescopeSpec()``).
    atmosphere : sequence of AtmosphereSpec
        Atmospheric parameters.
    ao_mode : {"SCAO", "SLAO", "GLAO", "MOAO", "LTAO", "MCAO"}, optional
        Default: ``"SCAO"`` with one corrector, ``"MCAO"`` with several.
    name : str, optional
        System name.
    config : str, optional
        Free-form configuration text (e.g. the simulator's configuration as TOML).
        FITS cards hold printable ASCII only: other text (newlines, non-ASCII) is
        stored JSON-quoted; :func:`config_of` gives it back.
    date_beginning : datetime.datetime, optional
        Start of the recording (UTC).

    Returns
    -------
    aotpy.AOSystem
        The system; write it with ``modalinfo.io.aot.write_system``.

    Raises
    ------
    ValueError
        Duplicate uids, a loop naming an unknown sensor or corrector, an unknown
        ``kind``, or no loop.
    """
    aotpy = import_aotpy()
    loops = list(loops)
    if not loops:
        raise ValueError("`loops` must hold at least one LoopSpec; got none.")
    telescope = TelescopeSpec() if telescope is None else telescope
    sources = list(sources)
    if not sources and any(s.source == "source" for s in sensors):
        sources = [SourceSpec()]
    src_specs = _by_uid(sources, "sources")
    sen_specs = _by_uid(sensors, "sensors")
    cor_specs = _by_uid(correctors, "correctors")
    _by_uid(loops, "loops")
    geometry: dict[str, dict] = {}

    def remember(kind: str, uid: str, values: dict) -> None:
        values = {k: v for k, v in values.items() if v is not None and v != {}}
        if values:
            geometry.setdefault(kind, {})[uid] = values

    tel = aotpy.MainTelescope(
        uid=telescope.uid,
        enclosing_diameter=telescope.diameter,
        inscribed_diameter=telescope.diameter if telescope.obscuration_diameter is None else None,
        obstruction_diameter=telescope.obscuration_diameter,
        pupil_mask=_image(aotpy, f"{telescope.uid} PUPIL", None if telescope.pupil_mask is None
                          else np.asarray(telescope.pupil_mask).astype(np.int16)),
        elevation=telescope.elevation,
        azimuth=telescope.azimuth,
    )
    src_kinds = {"natural": aotpy.NaturalGuideStar, "science": aotpy.ScienceStar}
    srcs = {}
    for s in src_specs.values():
        if s.kind not in src_kinds:
            raise ValueError(f"source {s.uid!r}: `kind` must be one of {list(src_kinds)}; "
                             f"got {s.kind!r}.")
        srcs[s.uid] = src_kinds[s.kind](uid=s.uid, elevation_offset=s.elevation_offset,
                                        azimuth_offset=s.azimuth_offset, fwhm=s.fwhm)
        remember("sources", s.uid, {"extra": s.extra})
    # times: one per loop, shared with its sensor's measurements when they have its length
    times = {}
    for lp in loops:
        if lp.timestamps is not None:
            times[lp.uid] = aotpy.Time(uid=f"{lp.uid} TIME",
                                       timestamps=list(np.asarray(lp.timestamps, dtype=np.float64)))
    wfss = {}
    for s in sen_specs.values():
        if s.source not in srcs:
            raise ValueError(f"sensor {s.uid!r} names source {s.source!r}, which is not among "
                             f"the sources {list(srcs)}.")
        time = None
        if s.measurements is not None:
            for lp in loops:
                if lp.sensor == s.uid and lp.uid in times and len(
                    lp.timestamps
                ) == np.shape(s.measurements)[0]:
                    time = times[lp.uid]
                    break
        common = dict(
            uid=s.uid, source=srcs[s.source], n_valid_subapertures=int(s.n_valid_subapertures),
            measurements=_image(aotpy, f"{s.uid} MEASUREMENTS", s.measurements, time=time,
                                unit=s.units),
            subaperture_mask=_image(aotpy, f"{s.uid} SUBAPERTURE_MASK", s.subaperture_mask),
            wavelength=s.wavelength,
        )
        if s.kind == "shack-hartmann":
            wfss[s.uid] = aotpy.ShackHartmann(**common)
        elif s.kind == "pyramid":
            dims = {} if s.dimensions is None else {"dimensions": int(s.dimensions)}
            wfss[s.uid] = aotpy.Pyramid(**common, n_sides=int(s.n_sides), **dims)
        else:
            raise ValueError(f"sensor {s.uid!r}: `kind` must be 'shack-hartmann' or 'pyramid'; "
                             f"got {s.kind!r}.")
        remember("sensors", s.uid, {"field_of_view": s.field_of_view, "altitude": s.altitude,
                                    "extra": s.extra})
    wfcs = {}
    for c in cor_specs.values():
        mask = None if c.pupil_mask is None else np.asarray(c.pupil_mask).astype(np.int16)
        if c.kind == "dm":
            wfcs[c.uid] = aotpy.DeformableMirror(
                uid=c.uid, telescope=tel, n_valid_actuators=int(c.n_valid_actuators),
                pupil_mask=_image(aotpy, f"{c.uid} PUPIL", mask),
                influence_function=_image(aotpy, f"{c.uid} INFLUENCE", c.influence_function,
                                          unit="m"),
            )
        elif c.kind == "tip-tilt":
            wfcs[c.uid] = aotpy.TipTiltMirror(uid=c.uid, telescope=tel,
                                              pupil_mask=_image(aotpy, f"{c.uid} PUPIL", mask))
        else:
            raise ValueError(f"corrector {c.uid!r}: `kind` must be 'dm' or 'tip-tilt'; "
                             f"got {c.kind!r}.")
        remember("correctors", c.uid, {"altitude": c.altitude, "extra": c.extra})
    aot_loops = []
    written_modes: dict[int, tuple] = {}

    def shared_modes(lp):
        # one array given to several loops (a DM's residual and its POL) is one image,
        # written once and referenced by each (aotpy writes the same Image object once)
        if lp.modes is None:
            return None
        if id(lp.modes) not in written_modes:
            written_modes[id(lp.modes)] = (lp.modes, _image(aotpy, f"{lp.uid} MODES", lp.modes))
        return written_modes[id(lp.modes)][1]

    for lp in loops:
        if lp.sensor not in wfss:
            raise ValueError(f"loop {lp.uid!r} names sensor {lp.sensor!r}, which is not among "
                             f"the sensors {list(wfss)}.")
        if lp.corrector not in wfcs:
            raise ValueError(f"loop {lp.uid!r} names corrector {lp.corrector!r}, which is not "
                             f"among the correctors {list(wfcs)}.")
        time = times.get(lp.uid)
        aot_loops.append(aotpy.ControlLoop(
            uid=lp.uid,
            input_sensor=wfss[lp.sensor],
            commanded_corrector=wfcs[lp.corrector],
            time=time,
            closed=bool(lp.closed),
            framerate=None if lp.framerate is None else float(lp.framerate),
            delay=None if lp.delay is None else float(lp.delay),
            modal_coefficients=_image(aotpy, f"{lp.uid} MODAL_COEFFICIENTS",
                                      lp.modal_coefficients, unit=lp.units, time=time,
                                      metadata=lp.coefficient_metadata),
            modes=shared_modes(lp),
            measurements_to_modes=_image(aotpy, f"{lp.uid} MEASUREMENTS_TO_MODES",
                                         lp.measurements_to_modes),
            modes_to_commands=_image(aotpy, f"{lp.uid} MODES_TO_COMMANDS", lp.modes_to_commands),
            commands=_image(aotpy, f"{lp.uid} COMMANDS", lp.commands, unit=lp.command_units,
                            time=time),
            time_filter_num=_image(aotpy, f"{lp.uid} TIME_FILTER_NUM", lp.time_filter_num),
            time_filter_den=_image(aotpy, f"{lp.uid} TIME_FILTER_DEN", lp.time_filter_den),
        ))
    atmos = []
    for a in _by_uid(atmosphere, "atmosphere parameters").values():
        def row(v, _a=a):
            return None if v is None else np.asarray(v, dtype=np.float64).reshape(1, -1)
        atmos.append(aotpy.AtmosphericParameters(
            uid=a.uid, wavelength=a.wavelength, r0=[] if a.r0 is None else [float(a.r0)],
            layers_relative_weight=_image(aotpy, f"{a.uid} LAYERS_WEIGHT", row(a.weights)),
            layers_height=_image(aotpy, f"{a.uid} LAYERS_HEIGHT", row(a.heights), unit="m"),
            layers_l0=_image(aotpy, f"{a.uid} LAYERS_L0", row(a.outer_scales), unit="m"),
            layers_wind_speed=_image(aotpy, f"{a.uid} LAYERS_WIND_SPEED", row(a.wind_speeds),
                                     unit="m/s"),
            layers_wind_direction=_image(aotpy, f"{a.uid} LAYERS_WIND_DIRECTION",
                                         row(a.wind_directions), unit="deg"),
        ))
    if ao_mode is None:
        ao_mode = "SCAO" if len(wfcs) <= 1 else "MCAO"
    metadata = []
    if geometry:
        text = json.dumps(geometry, ensure_ascii=True, allow_nan=False, separators=(",", ":"))
        metadata.append(aotpy.Metadatum(AOT_EXTRA_KEY, text))
    if config is not None and not (config.isascii() and config.isprintable()):
        config = json.dumps(config, ensure_ascii=True)
    return aotpy.AOSystem(
        ao_mode=ao_mode, name=name, config=config, date_beginning=date_beginning,
        main_telescope=tel, sources=list(srcs.values()), wavefront_sensors=list(wfss.values()),
        wavefront_correctors=list(wfcs.values()), loops=aot_loops, atmosphere_params=atmos,
        metadata=metadata,
    )


def config_of(system) -> str | None:
    """Return a system's configuration text, undoing the JSON quoting of build_system."""
    text = getattr(system, "config", None)
    if isinstance(text, str) and len(text) >= 2 and text[0] == text[-1] == '"':
        try:
            value = json.loads(text)
        except json.JSONDecodeError:
            return text
        return value if isinstance(value, str) else text
    return text


def geometry_of(system) -> dict[str, Any]:
    """Return the ``MI_GEOM`` extras of a system (``{}`` when absent or unreadable).

    Returns
    -------
    dict
        ``{"sensors": {uid: {...}}, "correctors": {uid: {"altitude": ...}}, ...}``.
    """
    for md in getattr(system, "metadata", None) or []:
        if md.key == AOT_EXTRA_KEY and isinstance(md.value, str):
            try:
                value = json.loads(md.value)
            except json.JSONDecodeError:
                return {}
            return value if isinstance(value, dict) else {}
    return {}
