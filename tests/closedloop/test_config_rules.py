"""Every documented rule of a config value, checked at its boundary, by key and value.

References (outside the code): the ranges the config's docstrings state for each key
(``TelescopeConfig`` ... ``SimulationConfig``; ``modalinfo.servo.MAX_DELAY_FRAMES`` for
the delay, ``FULL_WELL`` and one photo-electron for a correlating sensor's signal, 0.1 % for
its contrast), written
out here as a table:
the boundary value itself is accepted (stored as a plain ``float``/``int`` even when
given as a numpy scalar, so that the JSON and TOML writers take it), the value just
outside is refused with a message naming the full key (``layers[0].wind_speed``), the
rule and the value. Round trips through ``json`` and ``tomllib`` (other parsers) for the
plain form.
"""

from __future__ import annotations

import dataclasses
import json
import math
import tomllib

import numpy as np
import pytest

from closedloop.config import (
    ARCSEC,
    FULL_WELL,
    DMConfig,
    FieldConfig,
    LayerConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
    airmass,
    config_text,
    dm_disc_diameter,
    load_config,
    save_config,
    wfs_meta_pupil,
)
from modalinfo.servo import MAX_DELAY_FRAMES

#: the smallest config the rules allow: 8 pixels across 1 m, one layer, Z2-Z3 on one DM,
#: a 2x2 SH on axis, one science direction. D/r0 = 2: r0 = 50 cm stays above the 12.5 cm
#: pixel at the 75 degree zenith angle (r0 x cos(z)^(3/5) = 22 cm), the r0-sampling rule
BASE = SimulationConfig(
    telescope=TelescopeConfig(diameter=1.0, n_pixels=8),
    layers=(LayerConfig(altitude=0.0, d_over_r0=2.0, wind_speed=10.0),),
    dms=(DMConfig(altitude=0.0, n_modes=2),),
    wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=2, field_samples=1),),
    field=FieldConfig(size=0.0, n_points=1),
)

#: a correlating sensor: its field must hold 8 pixels of 0.5"
CORRELATING = {"kind": "correlating", "field_of_view": 4.0}


def _with(path: str, value, extra: dict | None = None) -> dict:
    """BASE's plain form with ``path`` (``"layers[0].wind_speed"``) set to ``value``."""
    d = BASE.to_dict()
    *heads, last = path.split(".")
    node = d
    for head in heads:
        name, _, index = head.partition("[")
        node = node[name] if not index else node[name][int(index.rstrip("]"))]
    node.update(extra or {})
    node[last] = value
    return d


def _get(config, path: str):
    node = config
    for head in path.split("."):
        name, _, index = head.partition("[")
        node = getattr(node, name) if not index else getattr(node, name)[int(index.rstrip("]"))]
    return node


# (key, accepted boundary values, refused values just outside, other keys of the table)
RULES = [
    # 0.05 m: the smallest BASE holds with its 10 m/s wind (v T <= D) and r0 >= one pixel
    ("telescope.diameter", [0.05, 1.0], [0.0, -1.0], None),
    # 0.95 itself leaves no subaperture centre of the 2x2 SH on the annulus (0 slopes for
    # the DM's 2 modes): 0.7 keeps the four centres (rho = 0.707)
    ("telescope.obscuration", [0.0, 0.7], [-0.01, 0.951], None),
    ("telescope.zenith_angle", [0.0, 75.0], [-0.5, 75.5], None),
    ("telescope.n_pixels", [8, 9], [7], None),
    ("layers[0].altitude", [0.0], [-1.0], None),
    ("layers[0].d_over_r0", [1e-3], [0.0], None),
    ("layers[0].wind_speed", [0.0], [-0.1], None),
    ("layers[0].wind_direction", [-360.0, 0.0, 360.0], [math.inf, -360.5, 360.5], None),
    ("layers[0].outer_scale", [1.001, math.inf], [0.0, 1.0], None),  # L0 > D = 1 m
    ("dms[0].altitude", [0.0], [-1.0], None),
    ("wfss[0].altitude", [0.0, 1e-6], [-1.0, 2e-6], None),  # its DM's altitude, to 1e-6 m
    ("wfss[0].dm", [0], [-1], None),
    # 2: Z2-Z3, radial order 1 <= 0.9 x the 2 subapertures (issue 29's order rule, which
    # binds before the 2 x 4 slopes of the 2x2 SH and the pupil sampling's 14); 9: beyond
    # the 8 slopes (the slopes rule)
    ("dms[0].n_modes", [1, 2], [0, 3, 9], None),
    # valid at and above telescope.diameter: a smaller disc warns (round 53 PART a)
    ("dms[0].diameter", [1.0, 1.5], [0.0], None),
    ("wfss[0].field_of_view", [0.0], [-1.0], None),
    ("wfss[0].n_subapertures", [2, 4], [1], None),  # 4: 2 pixels each across 8
    ("wfss[0].noise", [0.0, 0.01], [-1e-9], None),
    ("wfss[0].field_samples", [1, 2], [0], None),
    # 1e-300 (signal or contrast) was accepted; the run failed: "SVD did not converge" (k31)
    ("wfss[0].signal", [FULL_WELL, 1.0], [0.0, 0.999, 1e-300, FULL_WELL + 1.0], CORRELATING),
    ("wfss[0].contrast", [0.5, 0.01, 0.001], [0.0, 0.000999, 1e-300, 0.501], CORRELATING),
    ("wfss[0].pixel_scale", [0.5, 0.25], [0.0], CORRELATING),
    ("wfss[0].field_of_view", [4.0], [3.99], CORRELATING),  # >= 8 pixels of 0.5"
    ("loop.time_step", [1e-3], [0.0], None),
    ("loop.integration_time", [1e-3, 1e-4], [0.0, 1.001e-3], None),
    # a delay must be whole internal steps (time_step / n, n <= 64) at load: 1e-12 off is
    # 1e-9 frames off at the longest delay, refused
    ("loop.delay", [0.0, MAX_DELAY_FRAMES * 1e-3],
     [-1e-4, (MAX_DELAY_FRAMES + 1) * 1e-3, MAX_DELAY_FRAMES * 1e-3 * (1 + 1e-12)],
     {"gain": 1e-3}),  # a gain stable at 1000 frames (limit 1.6e-3, see modalinfo.servo)
    ("loop.gain", [1e-3], [0.0], None),
    ("loop.leak", [0.0, 0.999], [-0.01, 0.9991], None),
    ("loop.model_error", [0.0], [-0.1], None),
    ("field.size", [0.0], [-1.0], None),
    ("field.n_points", [1], [0, 2, -1, 3], None),  # a field of size 0 is the axis alone
    ("wavelength", [3e-7, 2.8e-5], [0.0, 2.99e-7, 2.81e-5], None),  # 300 nm - 28 um
    ("r0_wavelength", [3e-7, 2.8e-5], [0.0, 2.99e-7, 2.81e-5], None),
    ("seed", [0, 7], [-1], None),
]


def _numpy(value):
    """The same value as a numpy scalar (float32 where exact), as a user's array gives it."""
    if isinstance(value, int):
        return np.int64(value)
    return np.float32(value) if float(np.float32(value)) == value else np.float64(value)


@pytest.mark.parametrize("key,accepted,refused,extra", RULES,
                         ids=[f"{r[0]}{'-corr' if r[3] else ''}" for r in RULES])
# the layer rule's smallest accepted D/r0, 1e-3, is a total r0 of 1 km: warned, kept
@pytest.mark.filterwarnings("ignore:`total r0 .* is beyond 1 m at 500 nm:UserWarning")
def test_each_rule_at_its_boundary(key, accepted, refused, extra):
    for value in accepted:
        got = _get(SimulationConfig.from_dict(_with(key, _numpy(value), extra)), key)
        assert got == value and type(got) is type(value)  # a plain float / int
    for value in refused:
        with pytest.raises(ValueError) as info:
            SimulationConfig.from_dict(_with(key, value, extra))
        message = str(info.value)
        assert message.startswith(f"`{key}` must be") and f"got {value!r}" in message, message


@pytest.mark.parametrize("key,value", [
    ("telescope.diameter", "1"), ("telescope.n_pixels", 8.0), ("layers[0].altitude", None),
    ("dms[0].n_modes", True), ("wfss[0].dm", 0.0), ("field.n_points", "3"),
    ("loop.closed", 1), ("wfss[0].image_formation", 0), ("name", 3), ("seed", 1.0),
])
def test_wrong_types_are_refused_by_key(key, value):
    with pytest.raises(TypeError) as info:
        SimulationConfig.from_dict(_with(key, value))
    assert str(info.value).startswith(f"`{key}` must be"), info.value


@pytest.mark.parametrize("key,value,named,rule", [
    ("dms[0].kind", "zonal", None, "one of 'zernike', 'ideal'"),
    ("wfss[0].kind", "pyramid", None, "one of 'shack_hartmann', 'ideal', 'correlating'"),
    ("wfss[0].pixel_scale", 0.6, None, "left at its default (0.5) for kind 'shack_hartmann'"),
    ("wfss[0].signal", 100.0, None, "left at its default (None)"),
    ("wfss[0].contrast", 0.1, None, "left at its default (None)"),
    ("wfss[0].image_formation", True, None, "left at its default (False)"),
    ("wfss[0].altitude", 10.0, None, "the altitude of the DM it drives (dms[0].altitude = 0 m)"),
    ("wfss[0].dm", 1, "wfss[*].dm", "each DM index 0..0 exactly once"),
    # Z16 has radial order 5 > 8 pixels / 2 per cycle: Z2-Z15 (14 modes) is the limit
    ("dms[0].n_modes", 15, None, "<= 14 (Zernike radial order <= pixels across the DM's disc "
     "/ 2 = 4 for 8 pixels at telescope.n_pixels = 8; 15 modes reach order 5)"),
    ("wfss[0].n_subapertures", 5, None, "<= 4 (at least 2 pixels per subaperture across the "
     "8-pixel meta-pupil at telescope.n_pixels = 8)"),
])
def test_choices_and_cross_rules_name_the_key(key, value, named, rule):
    with pytest.raises(ValueError) as info:
        SimulationConfig.from_dict(_with(key, value))
    message = str(info.value)
    assert message.startswith(f"`{named or key}` must be {rule}"), message
    assert message.endswith(f"; got {value!r}.") or named, message


def test_correlating_sensor_refuses_a_hand_set_noise():
    d = _with("wfss[0].noise", 0.005, CORRELATING)
    with pytest.raises(ValueError, match=r"^`wfss\[0\]\.noise` must be 0 for kind 'correlating'"):
        SimulationConfig.from_dict(d)
    SimulationConfig.from_dict(_with("wfss[0].noise", 0.0, CORRELATING))


def test_one_wfs_per_dm_and_lists():
    d = BASE.to_dict()
    d["wfss"] = d["wfss"] * 2
    with pytest.raises(ValueError, match=r"^`wfss` must be one WFS per DM \(1 DMs\); got '2 WFSs'"):
        SimulationConfig.from_dict(d)
    for key in ("layers", "dms", "wfss"):
        d = BASE.to_dict()
        d[key] = []
        with pytest.raises(ValueError, match=f"^`{key}` must be a non-empty list"):
            SimulationConfig.from_dict(d)
        d[key] = {"x": 1}
        with pytest.raises(TypeError, match=f"^`{key}` must be a list of tables; got 'dict'"):
            SimulationConfig.from_dict(d)
        d[key] = [3]
        with pytest.raises(TypeError, match=rf"^`{key}\[0\]` must be a table \(dict\); got 'int'"):
            SimulationConfig.from_dict(d)
    for key in ("telescope", "loop", "field"):
        d = BASE.to_dict()
        d[key] = [1]
        with pytest.raises(TypeError, match=rf"^`{key}` must be a table \(dict\); got 'list'"):
            SimulationConfig.from_dict(d)
        with pytest.raises(TypeError, match=f"^`{key}` must be a "):
            BASE.replace(**{key: None})
    with pytest.raises(TypeError, match=r"^`config` must be a dict \(a table\); got 'list'"):
        SimulationConfig.from_dict([])
    with pytest.raises(TypeError, match=r"^`dms` must be a list of DMConfig; got 'DMConfig'"):
        BASE.replace(dms=BASE.dms[0])
    with pytest.raises(TypeError, match=r"^`dms\[0\]` must be a DMConfig; got 'WFSConfig'"):
        BASE.replace(dms=BASE.wfss)
    assert BASE.replace(dms=list(BASE.dms)).dms == BASE.dms  # a list is kept as a tuple


def test_plain_form_leaves_defaults_out_and_round_trips_through_other_parsers(tmp_path):
    d = BASE.to_dict()
    # None (dms[0].diameter, signal, contrast), inf (outer_scale) and the keys added later
    # at their defaults (pixel_scale, image_formation, loop.closed) are left out
    assert set(d["dms"][0]) == {"altitude", "n_modes", "kind"}
    assert set(d["wfss"][0]) == {"altitude", "field_of_view", "n_subapertures", "noise",
                                 "kind", "field_samples", "dm"}
    assert set(d["layers"][0]) == {"altitude", "d_over_r0", "wind_speed", "wind_direction"}
    assert "closed" not in d["loop"] and set(d) == {
        "name", "seed", "wavelength", "r0_wavelength", "telescope", "loop", "field",
        "layers", "dms", "wfss"}
    corr = SimulationConfig.from_dict(_with("wfss[0].signal", 100.0, CORRELATING))
    plain = corr.to_dict()["wfss"][0]
    assert plain["signal"] == 100.0 and "pixel_scale" not in plain
    opened = BASE.replace(loop=dataclasses.replace(BASE.loop, closed=False))
    assert opened.to_dict()["loop"]["closed"] is False
    for config in (BASE, corr, opened):
        assert SimulationConfig.from_dict(json.loads(config_text(config, "json"))) == config
        assert SimulationConfig.from_dict(tomllib.loads(config_text(config))) == config
    assert config_text(BASE).startswith('name = "custom"\nseed = 0\n')
    assert config_text(BASE, "json").startswith('{\n  "name": "custom",\n  "seed": 0,')
    with pytest.raises(ValueError, match="^`fmt` must be one of 'toml', 'json'; got 'yaml'"):
        config_text(BASE, "yaml")


def test_files_by_extension_never_replaced_unasked(tmp_path):
    for suffix in (".toml", ".json", ".TOML"):
        path = tmp_path / f"c{suffix}"
        assert save_config(BASE, path) == path
        text = path.read_text(encoding="utf-8")
        parsed = tomllib.loads(text) if suffix.lower() == ".toml" else json.loads(text)
        assert SimulationConfig.from_dict(parsed) == BASE == load_config(path)
        with pytest.raises(FileExistsError):
            save_config(BASE.replace(seed=3), path)
        assert path.read_text(encoding="utf-8") == text
        save_config(BASE.replace(seed=3), path, overwrite=True)
        assert load_config(path).seed == 3
    for bad in ("c.yaml", "c"):
        with pytest.raises(ValueError, match=f"^`path` must end in .toml or .json; got '.*{bad}'"):
            save_config(BASE, tmp_path / bad)
        with pytest.raises(ValueError, match=f"^`path` must end in .toml or .json; got '.*{bad}'"):
            load_config(tmp_path / bad)
    with pytest.raises(FileNotFoundError, match="config file '.*none.toml' does not exist"):
        load_config(tmp_path / "none.toml")
    for suffix, text, kind in ((".toml", "a = [", "TOML"), (".json", "{", "JSON")):
        path = tmp_path / f"broken{suffix}"
        path.write_text(text, encoding="utf-8")
        with pytest.raises(ValueError, match=f"broken{suffix}': not valid {kind}: "):
            load_config(path)


def test_missing_and_unknown_keys_are_named():
    d = BASE.to_dict()
    del d["wfss"][0]["field_of_view"]
    with pytest.raises(ValueError, match=r"^`wfss\[0\]\.field_of_view` is required in the config"):
        SimulationConfig.from_dict(d)
    d = BASE.to_dict()
    d["colour"] = 1
    with pytest.raises(ValueError, match="^unknown key `colour` in the config; allowed keys "
                       "there: dms, field, layers, loop, name, r0_wavelength, seed, "
                       "telescope, wavelength, wfss"):
        SimulationConfig.from_dict(d)
    d = BASE.to_dict()
    d["field"]["zz"] = 1
    d["field"]["aa"] = 1
    with pytest.raises(ValueError, match=r"^unknown key `field\.aa` in the config; allowed "
                       "keys there: n_points, size"):
        SimulationConfig.from_dict(d)


def test_meta_pupils_follow_the_documented_geometry():
    # D + 2 h sec(z) tan(fov / 2): 60 deg from the zenith (sec z = 2), a DM at 10 km
    # sensed over 60"; an explicit diameter wins; the ground is the pupil
    c = SimulationConfig(
        telescope=TelescopeConfig(diameter=1.0, n_pixels=8, zenith_angle=60.0),
        layers=BASE.layers,
        dms=(DMConfig(altitude=0.0, n_modes=2), DMConfig(altitude=10_000.0, n_modes=2),
             DMConfig(altitude=5_000.0, n_modes=2, diameter=1.5)),
        wfss=(WFSConfig(altitude=0.0, field_of_view=60.0, n_subapertures=2, dm=0),
              WFSConfig(altitude=10_000.0, field_of_view=60.0, n_subapertures=2, dm=1),
              WFSConfig(altitude=5_000.0, field_of_view=20.0, n_subapertures=2, dm=2)),
        field=BASE.field)
    arcsec = math.pi / 180 / 3600
    assert ARCSEC == arcsec
    assert airmass(c) == pytest.approx(2.0, rel=1e-12)
    assert wfs_meta_pupil(c, 0) == dm_disc_diameter(c, 0) == 1.0
    expected = 1.0 + 2 * 10_000.0 * 2.0 * math.tan(30.0 * arcsec)
    assert wfs_meta_pupil(c, 1) == pytest.approx(expected, rel=1e-12)
    assert dm_disc_diameter(c, 1) == pytest.approx(expected, rel=1e-12)
    assert dm_disc_diameter(c, 2) == 1.5
    assert wfs_meta_pupil(c, 2) == pytest.approx(1.0 + 2 * 5_000.0 * 2.0 * math.tan(
        10.0 * arcsec), rel=1e-12)


def test_sampling_rules_skip_only_zonal_mirrors_and_ideal_sensors():
    # an ideal (zonal) DM and an ideal WFS first must not end the checks of the others
    dms = (DMConfig(altitude=0.0, kind="ideal", n_modes=500), DMConfig(altitude=0.0,
                                                                       n_modes=15))
    wfss = (WFSConfig(altitude=0.0, field_of_view=0.0, kind="ideal", n_subapertures=50),
            WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=2, dm=1))
    with pytest.raises(ValueError, match=r"^`dms\[1\]\.n_modes` must be <= 14"):
        BASE.replace(dms=dms, wfss=(dataclasses.replace(wfss[0], dm=0), wfss[1]))
    dms = (dms[0], dataclasses.replace(dms[1], n_modes=2))
    ok = BASE.replace(dms=dms, wfss=wfss)
    assert ok.dms[0].n_modes == 500 and ok.wfss[0].n_subapertures == 50
    for kind, extra in (("shack_hartmann", {}), ("correlating", {"field_of_view": 4.0})):
        bad = dataclasses.replace(wfss[1], n_subapertures=5, kind=kind, **extra)
        with pytest.raises(ValueError, match=r"^`wfss\[1\]\.n_subapertures` must be <= 4"):
            BASE.replace(dms=dms, wfss=(wfss[0], bad))


@pytest.mark.parametrize("key,value,message", [
    ("wfss[0].image_formation", 0, "a bool (false: linear sensor, true: images formed and "
     "correlated every frame); got 0."),
    ("loop.closed", 1, "a bool (true: closed loop, false: open loop); got 1."),
    ("name", 3, "a string; got 3."),
    ("loop.delay", 1.001, "<= 1000 frames (loop.time_step = 0.001 s: at most 1 s; the stable "
     "gain there is below 2e-3, no AO loop); got 1.001."),
    ("field.n_points", 2, "odd (the optical axis is on the grid); got 2."),
    ("wfss[0].dm", 1, None),
])
def test_whole_messages(key, value, message):
    with pytest.raises((TypeError, ValueError)) as info:
        SimulationConfig.from_dict(_with(key, value))
    if message is None:  # the cross rule names every WFS's DM
        message = "each DM index 0..0 exactly once; got [1]."
        key = "wfss[*].dm"
    assert str(info.value) == f"`{key}` must be {message}"


def test_whole_messages_of_correlating_sensors_and_sections():
    cases = [
        (_with("wfss[0].noise", 0.005, CORRELATING), "`wfss[0].noise` must be 0 for kind "
         "'correlating' (its noise follows from its photon budget: set `signal` and "
         "`contrast`); got 0.005."),
        (_with("wfss[0].field_of_view", 3.5, CORRELATING), "`wfss[0].field_of_view` must be "
         ">= 8 detector pixels of pixel_scale = 0.5\" for kind 'correlating' (a subaperture "
         "image to correlate); got 3.5."),
    ]
    for d, message in cases:
        with pytest.raises(ValueError) as info:
            SimulationConfig.from_dict(d)
        assert str(info.value) == message
    for kwargs, message in (
            ({"telescope": {}}, "`telescope` must be a TelescopeConfig; got 'dict'."),
            ({"dms": {}}, "`dms` must be a list of DMConfig; got 'dict'."),
            ({"dms": ()}, "`dms` must be a non-empty list; got ()."),
    ):
        with pytest.raises((TypeError, ValueError)) as info:
            BASE.replace(**kwargs)
        assert str(info.value) == message
