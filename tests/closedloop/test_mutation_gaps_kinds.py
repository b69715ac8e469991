"""closedloop.kinds: the records' rules, the registry and its lookups, every message whole.

Gaps found by mutation testing (docs/MUTATION.md, "kinds.py, resources.py, predictors.py,
training.py"). References, from outside the code: the module's and the records'
docstrings (what a record must hold: an identifier name, callables where required,
callables or None where optional, a frozen dataclass of defaulted fields or None as
``options``, a tuple of str as ``fields``; a second record under a registered name is
refused, the same record again is harmless; an unknown name is refused naming the key),
and the project's rule that a refusal names the argument, the rule and the value.
Records are built here with plain functions; the registry is restored after each test.
"""

from __future__ import annotations

import dataclasses
import re

import pytest

import closedloop  # noqa: F401  (registers the built-in kinds)
from closedloop import kinds
from closedloop.kinds import (
    MirrorCost,
    MirrorKind,
    SensorCost,
    SensorKind,
    mirror_kind,
    mirror_kinds,
    register_mirror_kind,
    register_sensor_kind,
    sensor_kind,
    sensor_kinds,
    unregister_mirror_kind,
    unregister_sensor_kind,
)


def _f(*args, **kwargs):
    return None


def _sensor(name="probe_sensor", **changes):
    return SensorKind(**{"name": name, "build": _f, "estimate": _f, "aot_record": _f,
                         "aot_layout": _f, **changes})


def _mirror(name="probe_mirror", **changes):
    return MirrorKind(**{"name": name, "build": _f, "estimate": _f, "aot_description": _f,
                         **changes})


@dataclasses.dataclass(frozen=True)
class _Options:
    gain: float = 1.0


@dataclasses.dataclass(frozen=True)
class _NoDefault:
    gain: float


@dataclasses.dataclass
class _NotFrozen:
    gain: float = 1.0


@pytest.fixture(autouse=True)
def _registry_restored():
    sensors, mirrors = dict(kinds._SENSORS), dict(kinds._MIRRORS)
    yield
    kinds._SENSORS.clear()
    kinds._SENSORS.update(sensors)
    kinds._MIRRORS.clear()
    kinds._MIRRORS.update(mirrors)


def test_the_cost_records_default_to_no_extra_cost():
    # SensorCost: no frame time, no key, all entries held at once (held_entries None)
    s = SensorCost(n_measurements=10.0, build_entries=20.0)
    assert (s.frame_seconds, s.frame_key, s.held_entries) == (0.0, "", None)
    m = MirrorCost(n_modes=3.0, shape_bytes=4.0, ops_per_pixel=5.0, driver="dms[0].n_modes")
    assert (m.setup_seconds, m.build_bytes) == (0.0, 0.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.n_measurements = 1.0


def test_a_record_defaults_to_no_options_rules_or_fields():
    for record in (_sensor(), _mirror()):
        assert record.options is None and record.validate is None and record.check is None
        assert record.fields == ()
    assert _sensor().measurement_count is None and _mirror().controlled_modes is None
    # the optional callables and a tuple of str are accepted
    ok = _sensor(options=_Options, validate=_f, check=_f, measurement_count=_f,
                 fields=("a", "b"))
    assert ok.options is _Options and ok.fields == ("a", "b")
    assert _mirror(options=_Options, validate=_f, check=_f, controlled_modes=_f).check is _f


@pytest.mark.parametrize("name", ["", "two words", "1st", 3, None])
def test_a_name_that_is_no_identifier_is_refused(name):
    msg = f"`kind.name` must be an identifier (a config's `kind`); got {name!r}."
    for make in (_sensor, _mirror):
        with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
            make(name=name)


@pytest.mark.parametrize("field", ["build", "estimate", "aot_record", "aot_layout"])
def test_each_required_sensor_callable_is_checked(field):
    with pytest.raises(TypeError, match="^" + re.escape(
            f"`kind.{field}` must be callable; got 42.") + "$"):
        _sensor(**{field: 42})


@pytest.mark.parametrize("field", ["build", "estimate", "aot_description"])
def test_each_required_mirror_callable_is_checked(field):
    with pytest.raises(TypeError, match="^" + re.escape(
            f"`kind.{field}` must be callable; got 'x'.") + "$"):
        _mirror(**{field: "x"})


@pytest.mark.parametrize("field", ["validate", "check", "measurement_count"])
def test_each_optional_sensor_callable_is_checked(field):
    with pytest.raises(TypeError, match="^" + re.escape(
            f"`kind.{field}` must be callable or None; got 1.") + "$"):
        _sensor(**{field: 1})


@pytest.mark.parametrize("field", ["validate", "check", "controlled_modes"])
def test_each_optional_mirror_callable_is_checked(field):
    with pytest.raises(TypeError, match="^" + re.escape(
            f"`kind.{field}` must be callable or None; got 1.") + "$"):
        _mirror(**{field: 1})


@pytest.mark.parametrize("options", [dict, _NotFrozen, _Options(), "opts"])
def test_options_must_be_a_frozen_dataclass_type(options):
    msg = f"`kind.options` must be a frozen dataclass type or None; got {options!r}."
    for make in (_sensor, _mirror):
        with pytest.raises(TypeError, match="^" + re.escape(msg) + "$"):
            make(options=options)


def test_options_without_a_default_are_refused_naming_the_field():
    msg = "`kind.options` fields must all have defaults; 'gain' has none."
    with pytest.raises(TypeError, match="^" + re.escape(msg) + "$"):
        _sensor(options=_NoDefault)

    @dataclasses.dataclass(frozen=True)
    class Factory:  # a default_factory is a default
        values: tuple = dataclasses.field(default_factory=tuple)
        first: float = 0.0

    assert _mirror(options=Factory).options is Factory

    @dataclasses.dataclass(frozen=True)
    class Second:  # the first field without a default is named
        a: float = 0.0
        b: float = dataclasses.field(default=0.0)
        c: int = dataclasses.field(default_factory=int)

    assert _sensor(options=Second).options is Second


@pytest.mark.parametrize("fields", [["a"], ("a", 1), "ab", (b"a",)])
def test_fields_must_be_a_tuple_of_str(fields):
    msg = f"`kind.fields` must be a tuple of str; got {fields!r}."
    for make in (_sensor, _mirror):
        with pytest.raises(TypeError, match="^" + re.escape(msg) + "$"):
            make(fields=fields)


def test_registering_adds_returns_and_lists_in_order_and_unregistering_removes():
    before_s, before_m = sensor_kinds(), mirror_kinds()
    assert before_s[:3] == ("shack_hartmann", "ideal", "correlating")
    assert before_m[:2] == ("zernike", "ideal") and "actuators" in before_m
    s, m = _sensor(), _mirror()
    assert register_sensor_kind(s) is s and register_mirror_kind(m) is m
    assert sensor_kinds() == (*before_s, "probe_sensor")
    assert mirror_kinds() == (*before_m, "probe_mirror")
    assert sensor_kind("probe_sensor") is s and mirror_kind("probe_mirror") is m
    # the same record (or an equal one) again is harmless
    assert register_sensor_kind(_sensor()) == s
    assert register_mirror_kind(m) is m and mirror_kinds() == (*before_m, "probe_mirror")
    # sensors and mirrors are separate tables: a mirror may take a sensor's name
    both = _mirror(name="probe_sensor")
    assert register_mirror_kind(both) is both and sensor_kind("probe_sensor") == s
    unregister_sensor_kind("probe_sensor")
    unregister_mirror_kind("probe_mirror")
    unregister_mirror_kind("probe_sensor")
    assert sensor_kinds() == before_s and mirror_kinds() == before_m


def test_a_wrong_record_type_is_refused_naming_the_type():
    with pytest.raises(TypeError, match=r"^`kind` must be a SensorKind; got MirrorKind\.$"):
        register_sensor_kind(_mirror())
    with pytest.raises(TypeError, match=r"^`kind` must be a MirrorKind; got SensorKind\.$"):
        register_mirror_kind(_sensor())
    with pytest.raises(TypeError, match=r"^`kind` must be a MirrorKind; got str\.$"):
        register_mirror_kind("zernike")


def test_another_record_under_a_registered_name_is_refused_and_the_first_kept():
    first = register_sensor_kind(_sensor())
    msg = "`kind.name` must be a new sensor kind; 'probe_sensor' is registered already."
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        register_sensor_kind(_sensor(fields=("x",)))
    assert sensor_kind("probe_sensor") is first
    register_mirror_kind(_mirror())
    msg = "`kind.name` must be a new mirror kind; 'probe_mirror' is registered already."
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        register_mirror_kind(_mirror(check=_f))


def test_unregistering_an_unknown_name_lists_the_registered_ones():
    names = ", ".join(map(repr, sensor_kinds()))
    msg = f"`name` must be a registered sensor kind ({names}); got 'nope'."
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        unregister_sensor_kind("nope")
    names = ", ".join(map(repr, mirror_kinds()))
    msg = f"`name` must be a registered mirror kind ({names}); got 'shack_hartmann'."
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        unregister_mirror_kind("shack_hartmann")


@pytest.mark.parametrize("name", ["nope", ["zernike"], None, 3])
def test_an_unknown_kind_is_refused_naming_the_key_and_the_choices(name):
    names = ", ".join(map(repr, mirror_kinds()))
    msg = f"`dms[1].kind` must be one of {names}; got {name!r}."
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        mirror_kind(name, "dms[1].kind")
    names = ", ".join(map(repr, sensor_kinds()))
    msg = f"`kind` must be one of {names}; got {name!r}."  # the default key
    with pytest.raises(ValueError, match="^" + re.escape(msg) + "$"):
        sensor_kind(name)
    with pytest.raises(ValueError, match=r"^`kind` must be one of 'zernike'"):
        mirror_kind(name)


def test_the_built_in_kinds_hold_their_modules_parts():
    from closedloop.optics import actuator_dm, dm, wfs

    assert sensor_kind("shack_hartmann") is wfs.SHACK_HARTMANN
    assert sensor_kind("ideal") is wfs.IDEAL
    assert mirror_kind("actuators") is actuator_dm.ACTUATORS
    assert mirror_kind("zernike") is dm.ZERNIKE and mirror_kind("ideal") is dm.IDEAL
    # the correlating SH's four keys predate `options` (SensorKind.fields' docstring)
    assert len(sensor_kind("correlating").fields) == 4
