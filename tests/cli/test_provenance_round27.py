"""Round 27 PART b of issue 27: forecast's figures record what made them.

docs/ADVERSARIAL.md, "Round 27 PART b, issue 27", row P09: forecast_rmse.png and
forecast_series.png carried only Matplotlib's ``Software`` key, so two figures of
different options could not be told apart once out of their folder.

References: ``hashlib.sha256`` of the input file's bytes; the PNG text chunks as
Pillow reads them (an independent PNG reader, not the code that wrote them); the
record in forecast.json beside the figures.
"""

from __future__ import annotations

import hashlib
import json

from PIL import Image

from .conftest import exit_code


def test_forecast_pngs_carry_the_provenance_record(make_small_log, tmp_path, capsys):
    log = make_small_log(400)
    out = tmp_path / "fc"
    argv = ["forecast", str(log), "--modes", "2", "--predictors", "linear", "--horizon",
            "2", "--out", str(out), "--quiet"]
    assert exit_code(argv) == 0, capsys.readouterr().err
    record = json.loads((out / "forecast.json").read_text())["provenance"]
    for name in ("forecast_rmse.png", "forecast_series.png"):
        with Image.open(out / name) as im:
            got = json.loads(im.info["Description"])
        assert got == record
        assert got["input"]["sha256"] == hashlib.sha256(log.read_bytes()).hexdigest()
        assert got["command"][1:] == argv
