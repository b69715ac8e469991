"""closedloop.config and presets: validation by key, TOML/JSON round trips.

References: round trips (to_dict -> TOML/JSON text -> from_dict gives an equal config),
the paper's Table 1 values typed from the paper, and the rule that every bad value is
named by its key.
"""

import math

import pytest

from closedloop import presets
from closedloop.config import (
    LayerConfig,
    SimulationConfig,
    config_text,
    load_config,
    save_config,
)


def test_table1_holds_the_papers_table():
    c = presets.get("table1")
    assert c.telescope.diameter == 4.0
    assert c.telescope.zenith_angle == 0.0
    assert c.loop.time_step == 1e-3 and c.loop.integration_time == 1e-3
    assert c.loop.delay == 0.5e-3
    assert len(c.dms) == 2 and len(c.layers) == 2
    assert [lay.d_over_r0 for lay in c.layers] == [26.0, 2.0]
    assert [lay.wind_speed for lay in c.layers] == [7.0, 70.0]
    assert all(math.isinf(lay.outer_scale) for lay in c.layers)  # Kolmogorov
    # perfect matching: DMs at the layers' altitudes
    assert [d.altitude for d in c.dms] == [lay.altitude for lay in c.layers]
    assert c.loop.oversampling == 2


@pytest.mark.parametrize("name", presets.names())
@pytest.mark.parametrize("fmt", ["toml", "json"])
def test_round_trip_text(name, fmt, tmp_path):
    c = presets.get(name)
    path = tmp_path / f"c.{fmt}"
    save_config(c, path)
    assert load_config(path) == c
    assert SimulationConfig.from_dict(c.to_dict()) == c
    with pytest.raises(FileExistsError):
        save_config(c, path)
    assert "table" in config_text(presets.get("table1"), fmt) or fmt == "json"


def test_finite_outer_scale_survives_and_inf_is_default():
    c = presets.get("table1")
    layers = (LayerConfig(altitude=0.0, d_over_r0=20.0, wind_speed=5.0, outer_scale=25.0),)
    c2 = c.replace(layers=layers, dms=c.dms[:1], wfss=c.wfss[:1])
    d = c2.to_dict()
    assert d["layers"][0]["outer_scale"] == 25.0
    assert "outer_scale" not in c.to_dict()["layers"][0]
    assert SimulationConfig.from_dict(d) == c2


@pytest.mark.parametrize("path,value,match", [
    (("layers", 1, "wind_speed"), -3.0, r"layers\[1\]\.wind_speed"),
    (("loop", "gain"), 0.0, r"loop\.gain"),
    (("loop", "integration_time"), 2e-3, r"loop\.integration_time"),
    (("field", "n_points"), 8, r"field\.n_points.*odd"),
    (("telescope", "diameter"), "4", r"telescope\.diameter.*real"),
    (("dms", 0, "kind"), "bimorph", r"dms\[0\]\.kind"),
    (("wfss", 1, "altitude"), 5000.0, r"wfss\[1\]\.altitude"),
])
def test_bad_values_name_their_key(path, value, match):
    d = presets.get("table1").to_dict()
    node = d
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    with pytest.raises((ValueError, TypeError), match=match):
        SimulationConfig.from_dict(d)


def test_unknown_and_missing_keys():
    d = presets.get("table1").to_dict()
    d["loop"]["gian"] = 0.3
    with pytest.raises(ValueError, match=r"unknown key `loop\.gian`"):
        SimulationConfig.from_dict(d)
    d = presets.get("table1").to_dict()
    del d["layers"][0]["d_over_r0"]
    with pytest.raises(ValueError, match=r"layers\[0\]\.d_over_r0` is required"):
        SimulationConfig.from_dict(d)
    with pytest.raises(ValueError, match="preset|name"):
        presets.get("nope")


def test_total_d_over_r0():
    c = presets.get("table1")
    assert c.d_over_r0 == pytest.approx((26 ** (5 / 3) + 2 ** (5 / 3)) ** 0.6)


def test_a_fifo_as_config_file_is_named_not_said_missing(tmp_path):
    # round 5: `closedloop config --config fifo.json` said "does not exist"
    import os

    from closedloop.config import load_config

    os.mkfifo(tmp_path / "cfg.json")
    with pytest.raises(FileNotFoundError, match="is not a regular file"):
        load_config(tmp_path / "cfg.json")
    with pytest.raises(FileNotFoundError, match="does not exist"):
        load_config(tmp_path / "missing.json")
