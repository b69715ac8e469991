"""Round 21 PART b: a command's output fed to the next command is named, not guessed.

Reference: the documents themselves - the ``format`` field a JSON output carries, the
header line of forecast.csv / batch.csv as those commands write it (copied from real
outputs), the keys of a ``closedloop config`` file. Before the fixes every JSON was "(a
result or config file?)", forecast.csv a "corrupt CSV file ... could not convert
'persistence'", and reorder's JSON given to ``closedloop run --config`` "unknown key
`basis_key`".
"""

import json

import pytest

from closedloop import load_config
from modalinfo.io import LogFormatError, load

ORDERING = {"format": "modalinfo.OrderingResult/1", "order": [1, 0], "labels": ["Z3", "Z2"],
            "basis_key": "zernike"}
FORECAST = {"names": ["persistence", "mean", "linear"], "horizons": [1], "rmse": [[[0.1]]],
            "labels": ["Z2"], "baseline": "persistence"}
ROW = {"analysis": "summary", "key": "3e1e", "status": "ok", "n_modes": 27}


@pytest.mark.parametrize("doc, words", [
    (ORDERING, "modalinfo.OrderingResult/1"),
    (FORECAST, "forecast.json"),
    (ROW, "result row of `modalinfo batch`"),
])
def test_json_outputs_are_named_as_logs(tmp_path, doc, words):
    path = tmp_path / "out.json"
    path.write_text(json.dumps(doc), encoding="utf-8")
    with pytest.raises(LogFormatError) as exc:
        load(path)
    assert words in str(exc.value) and "not a log" in str(exc.value)
    assert "?" not in str(exc.value)


def test_unknown_json_still_says_json(tmp_path):
    path = tmp_path / "o.json"
    path.write_text('{"a": 1}', encoding="utf-8")
    with pytest.raises(LogFormatError, match="holds JSON"):
        load(path)


@pytest.mark.parametrize("header, words", [
    ("predictor,mode,horizon,rmse,gain,coverage,dm_statistic,p_value,beats_baseline",
     "forecast.csv"),
    ('"path","analysis","status","sha256","version","params","hints","key"', "batch.csv"),
])
def test_result_tables_are_named_as_logs(tmp_path, header, words):
    path = tmp_path / "t.csv"
    path.write_text(header + "\npersistence,Z2,1,0.03,1.0,,,,\n", encoding="utf-8")
    with pytest.raises(LogFormatError) as exc:
        load(path)
    assert words in str(exc.value) and "corrupt" not in str(exc.value)


def test_a_result_is_not_read_as_a_closedloop_config(tmp_path):
    path = tmp_path / "ord.json"
    path.write_text(json.dumps(ORDERING), encoding="utf-8")
    with pytest.raises(ValueError) as exc:
        load_config(path)
    assert "OrderingResult" in str(exc.value) and "not a closedloop config" in str(exc.value)
    path.write_text(json.dumps(FORECAST), encoding="utf-8")
    with pytest.raises(ValueError, match="forecast.json"):
        load_config(path)


def test_a_closedloop_config_still_loads(tmp_path):
    from closedloop import presets, save_config

    saved = save_config(presets.get("kaos"), tmp_path / "k.json")
    assert load_config(saved) == presets.get("kaos")
