"""The registry of sensor and mirror kinds: one record per kind, everything the rest asks of it.

A configuration names each wavefront sensor's and deformable mirror's kind
(``wfss[j].kind``, ``dms[i].kind``). Everything the simulator asks of a kind is in its
record, a frozen :class:`SensorKind` or :class:`MirrorKind`, registered here by the
kind's own module (:func:`register_sensor_kind`, :func:`register_mirror_kind`):

===========================  =======================================================
who asks                     what (the record's field)
===========================  =======================================================
``closedloop.config``        the kind's name (``WFS_KINDS``/``DM_KINDS`` derive from
                             the registry), its own options (``options``, a frozen
                             dataclass whose fields are keys of the config's table),
                             their rules (``validate``) and its rules against the
                             pupil grid and the other parts (``check``,
                             ``measurement_count`` / ``controlled_modes``)
``closedloop.resources``     memory and time before any work (``estimate``)
``closedloop.model``         the part itself (``build``)
``closedloop.aot``           how it is written in an AO Telemetry file (``aot_record``
                             and ``aot_layout`` for a sensor, ``aot_description`` for
                             a mirror)
===========================  =======================================================

This module is on closedloop's ground floor beside ``config`` (it imports nothing of
the simulator): the records hold functions, so the config asks a kind without
importing its module. The built-in kinds are registered by their modules in
``closedloop/optics`` (``wfs``, ``correlating_sensor``, ``dm``, ``actuator_dm``), which
``closedloop/optics/__init__.py`` imports: that import list is the one place a new
built-in kind is added (docs/ARCHITECTURE.md, "To add a sensor kind / a DM kind").
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, fields, is_dataclass
from typing import Any

__all__ = ["SensorKind", "MirrorKind", "SensorCost", "MirrorCost", "register_sensor_kind",
           "register_mirror_kind", "unregister_sensor_kind", "unregister_mirror_kind",
           "sensor_kind", "mirror_kind", "sensor_kinds", "mirror_kinds"]


@dataclass(frozen=True)
class SensorCost:
    """What a sensor costs, estimated from the config alone (``SensorKind.estimate``).

    Attributes
    ----------
    n_measurements : float
        Measurements per frame (an estimate: the dense reconstructor's rows and the logs).
    build_entries : float
        Sparse entries its operators' assembly makes over all planes (16 bytes each,
        ``closedloop.resources``; the CSR operators it keeps are a share of them).
    frame_seconds : float
        Wall time per frame it adds beyond its sparse products [s] (image formation).
    frame_key : str
        The config key that drives ``frame_seconds`` (named when a run is refused).
    held_entries : float or None
        Of ``build_entries``, those held at once (the set-up's peak); None: all of them.
        A Shack-Hartmann assembles one plane at a time: a plane's share.
    """

    n_measurements: float
    build_entries: float
    frame_seconds: float = 0.0
    frame_key: str = ""
    held_entries: float | None = None


@dataclass(frozen=True)
class MirrorCost:
    """What a mirror costs, estimated from the config alone (``MirrorKind.estimate``).

    Attributes
    ----------
    n_modes : float
        Controlled modes (columns of the reconstructor, entries of a log row).
    shape_bytes : float
        Bytes of its shapes (and their tables) beyond the plane grids.
    ops_per_pixel : float
        Multiply-adds per disc pixel per surface update (its synthesis).
    driver : str
        The config key that drives ``shape_bytes`` (``dms[i].n_modes`` ...).
    setup_seconds : float
        CPU time to build it beyond its shapes' evaluation [s] (e.g. an eigen-decomposition
        for its modes; 0: negligible).
    build_bytes : float
        Bytes alive only while it is built (freed before the loop runs; e.g. the dense
        arrays of an eigen-decomposition; 0: none worth counting).
    """

    n_modes: float
    shape_bytes: float
    ops_per_pixel: float
    driver: str
    setup_seconds: float = 0.0
    build_bytes: float = 0.0


@dataclass(frozen=True)
class SensorKind:
    """Everything the simulator asks of one wavefront-sensor kind.

    Attributes
    ----------
    name : str
        The config's ``wfss[j].kind``.
    build : callable ``(geometry, index, dm) -> Sensor``
        The sensor of WFS ``index`` driving mirror ``dm`` (usually the class, a subclass
        of ``closedloop.optics.wfs.WavefrontSensor``).
    estimate : callable ``(config, j, n_planes, dx) -> SensorCost``
        Its memory and time, from the config alone (``dx``: pupil pixel [m]).
    aot_record : callable ``(model, j, wfs_config, measurements) -> SensorSpec``
        Its record in an AOT export (``modalinfo.io.aot_system.SensorSpec``);
        ``measurements`` is ``(T, d, s_v)`` or None.
    aot_layout : callable ``(sensor, array (rows, n_meas)) -> (rows, d, s_v)``
        Its measurement vector as AOT's ``(d, s_v)`` axes.
    options : type or None
        A frozen dataclass of the kind's own keys (each with a default); its fields are
        keys of the ``wfss[j]`` table and ``wfss[j].options`` holds an instance. None:
        the kind has no options of its own.
    validate : callable ``(wfs_config, prefix) -> None`` or None
        The kind's rules on its options and on the common keys (raise ValueError /
        TypeError naming ``prefix + key``).
    check : callable ``(config, j) -> None`` or None
        Its rules against the pupil grid (e.g. pixels per subaperture).
    measurement_count : callable ``(config, j) -> int`` or None
        Measurements it gives, for the rule "no more controlled modes than measurements";
        None: it measures the phase itself (no such rule).
    fields : tuple of str
        Keys of ``closedloop.config.WFSConfig`` only this kind uses: refused at
        non-default values by every other kind (the correlating SH's four keys, which
        predate ``options``; a new kind uses ``options``).
    """

    name: str
    build: Callable[..., Any]
    estimate: Callable[..., SensorCost]
    aot_record: Callable[..., Any]
    aot_layout: Callable[..., Any]
    options: type | None = None
    validate: Callable[..., None] | None = None
    check: Callable[..., None] | None = None
    measurement_count: Callable[..., int] | None = None
    fields: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        _check_record(self, "kind", ("build", "estimate", "aot_record", "aot_layout"),
                      ("validate", "check", "measurement_count"))


@dataclass(frozen=True)
class MirrorKind:
    """Everything the simulator asks of one deformable-mirror kind.

    Attributes
    ----------
    name : str
        The config's ``dms[i].kind``.
    build : callable ``(geometry, index) -> DeformableMirror``
        Mirror ``index`` (usually a subclass of
        ``closedloop.optics.dm.DeformableMirror``).
    estimate : callable ``(config, i, dx) -> MirrorCost``
        Its memory and time, from the config alone.
    aot_description : callable ``(mirror) -> dict``
        ``{"model": ..., "modes": ...}``: what its "actuators" are, for the AOT export.
    options, validate, check
        As for :class:`SensorKind` (keys of the ``dms[i]`` table; ``check(config, i)``).
    controlled_modes : callable ``(config, i) -> int`` or None
        Modes it controls (its shape matrix's columns), for the rule "no more controlled
        modes than measurements" and the joint MAP reconstructor; None: a zonal mirror
        without a shape matrix (one "mode" per disc pixel; no joint reconstructor).
    fields : tuple of str
        Keys of ``closedloop.config.DMConfig`` only this kind uses (see
        :class:`SensorKind`).
    """

    name: str
    build: Callable[..., Any]
    estimate: Callable[..., MirrorCost]
    aot_description: Callable[..., dict]
    options: type | None = None
    validate: Callable[..., None] | None = None
    check: Callable[..., None] | None = None
    controlled_modes: Callable[..., int] | None = None
    fields: tuple[str, ...] = field(default=())

    def __post_init__(self) -> None:
        _check_record(self, "kind", ("build", "estimate", "aot_description"),
                      ("validate", "check", "controlled_modes"))


def _check_record(record, arg: str, required: tuple[str, ...], optional: tuple[str, ...]) -> None:
    if not isinstance(record.name, str) or not record.name.isidentifier():
        raise ValueError(f"`{arg}.name` must be an identifier (a config's `kind`); "
                         f"got {record.name!r}.")
    for name in required:
        if not callable(getattr(record, name)):
            raise TypeError(f"`{arg}.{name}` must be callable; got {getattr(record, name)!r}.")
    for name in optional:
        value = getattr(record, name)
        if value is not None and not callable(value):
            raise TypeError(f"`{arg}.{name}` must be callable or None; got {value!r}.")
    opts = record.options
    if opts is not None and not (isinstance(opts, type) and is_dataclass(opts)
                                 and opts.__dataclass_params__.frozen):
        raise TypeError(f"`{arg}.options` must be a frozen dataclass type or None; got {opts!r}.")
    if opts is not None:
        missing = [f.name for f in fields(opts) if f.default is f.default_factory]
        if missing:  # both MISSING: the plain form may leave a key out
            raise TypeError(f"`{arg}.options` fields must all have defaults; "
                            f"{missing[0]!r} has none.")
    if not isinstance(record.fields, tuple) or not all(isinstance(f, str) for f in record.fields):
        raise TypeError(f"`{arg}.fields` must be a tuple of str; got {record.fields!r}.")


_SENSORS: dict[str, SensorKind] = {}
_MIRRORS: dict[str, MirrorKind] = {}


def _register(table: dict, record, cls: type, what: str):
    if not isinstance(record, cls):
        raise TypeError(f"`kind` must be a {cls.__name__}; got {type(record).__name__}.")
    if record.name in table and table[record.name] != record:
        raise ValueError(f"`kind.name` must be a new {what} kind; {record.name!r} is "
                         f"registered already.")
    table[record.name] = record
    return record


def register_sensor_kind(kind: SensorKind) -> SensorKind:
    """Register a sensor kind under ``kind.name``; return it.

    Registering the same record twice is harmless (a module imported again); another
    record under a registered name is refused with ``ValueError``.
    """
    return _register(_SENSORS, kind, SensorKind, "sensor")


def register_mirror_kind(kind: MirrorKind) -> MirrorKind:
    """Register a mirror kind under ``kind.name``; return it (see :func:`register_sensor_kind`)."""
    return _register(_MIRRORS, kind, MirrorKind, "mirror")


def _unregister(table: dict, name: str, what: str) -> None:
    if name not in table:
        raise ValueError(f"`name` must be a registered {what} kind "
                         f"({', '.join(map(repr, table))}); got {name!r}.")
    del table[name]


def unregister_sensor_kind(name: str) -> None:
    """Remove a registered sensor kind (a plug-in's or a test's)."""
    _unregister(_SENSORS, name, "sensor")


def unregister_mirror_kind(name: str) -> None:
    """Remove a registered mirror kind (a plug-in's or a test's)."""
    _unregister(_MIRRORS, name, "mirror")


def _lookup(table: dict, name, key: str):
    try:
        return table[name]
    except (KeyError, TypeError):  # TypeError: an unhashable value
        pass
    raise ValueError(f"`{key}` must be one of {', '.join(map(repr, table))}; got {name!r}.")


def sensor_kind(name: str, key: str = "kind") -> SensorKind:
    """Return the registered sensor kind ``name``; ``ValueError`` naming ``key`` if unknown."""
    return _lookup(_SENSORS, name, key)


def mirror_kind(name: str, key: str = "kind") -> MirrorKind:
    """Return the registered mirror kind ``name``; ``ValueError`` naming ``key`` if unknown."""
    return _lookup(_MIRRORS, name, key)


def sensor_kinds() -> tuple[str, ...]:
    """Names of the registered sensor kinds, in registration order."""
    return tuple(_SENSORS)


def mirror_kinds() -> tuple[str, ...]:
    """Names of the registered mirror kinds, in registration order."""
    return tuple(_MIRRORS)
