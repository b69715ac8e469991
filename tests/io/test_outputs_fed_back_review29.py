"""Result tables and TOML files fed back as logs, at the edges of their rules (review29).

Round 29 X1 / X3 (modalinfo/io/formats.py:292 / 248, round 46 PART b): ``result_table``
reads the first line "after a BOM and blank space", as ``detect_format`` does, and a
``.toml`` suffix is matched in any case. Planted slips (the BOM no longer stripped; the
suffix compared as written) passed every test, whose files had neither. References,
outside the package: Python's ``utf-8-sig`` codec writing the BOM (as a spreadsheet
re-saving a CSV does), the file re-read by ``Path.read_bytes``, and the round 46 texts.
"""

import pytest

from modalinfo.io import load
from modalinfo.io.formats import LogFormatError, result_table

_SWEEP_CSV = ('"override","seed","predictor","status","averaged_from_s","closed"\n'
              '"base",0,"none","ok",0.004,true\n')
_GRID_TOML = 'preset = "kaos"\nduration = 0.02\nseeds = [0]\n\n[[overrides]]\nname = "g"\n'


def test_a_result_table_saved_with_a_bom_is_named(tmp_path):
    path = tmp_path / "sweep.csv"
    path.write_text(_SWEEP_CSV, encoding="utf-8-sig")
    assert path.read_bytes().startswith(b"\xef\xbb\xbf\"override\"")
    what = "sweep.csv, the result table of `closedloop sweep`"
    assert result_table(path) == what
    with pytest.raises(LogFormatError, match="not a log") as info:
        load(path)
    assert what in str(info.value)


def test_an_upper_case_toml_suffix_is_named(tmp_path):
    path = tmp_path / "GRID.TOML"
    path.write_text(_GRID_TOML, encoding="utf-8")
    with pytest.raises(LogFormatError, match=r"is a closedloop sweep grid, for `closedloop "
                                             r"sweep GRID`, not a log"):
        load(path)
