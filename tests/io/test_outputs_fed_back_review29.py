"""Result tables and TOML files fed back as logs, at the edges of their rules (review29).

Round 29, planted in modalinfo/io/formats.py (round 46 PART b's naming of outputs fed
back), each passing every test before: X1 (:292) ``result_table`` reads the first line
"after a BOM and blank space", as ``detect_format`` does, planted without the BOM; X3
(:248) a ``.toml`` suffix matched in any case, planted as written; X4 (:323) an empty
document called a sweep grid (``keys <= GRID_KEYS`` holds for no keys); X5 (:317) a
sweep row named by one of its four keys; X6 (:335) the 64 MiB parse limit of a TOML
file read as 64 KiB. References, outside the package: Python's ``utf-8-sig`` codec
writing the BOM (as a spreadsheet re-saving a CSV does), the file re-read by
``Path.read_bytes``, ``tomllib`` reading what is written, and the round 46 texts.
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


@pytest.mark.parametrize(("text", "why"), [
    ("# no key yet\n", "no key, so no grid"),
    ('status = "ok"\n', "one key of a sweep row's four"),
])
def test_a_toml_of_no_known_kind_is_not_named_a_result(tmp_path, text, why):
    import tomllib

    path = tmp_path / "x.toml"
    path.write_text(text, encoding="utf-8")
    assert len(tomllib.loads(text)) <= 1, why
    with pytest.raises(LogFormatError, match=r"is a TOML file \(a config\?\), not a log"):
        load(path)


def test_a_grid_with_long_comments_is_still_named(tmp_path):
    path = tmp_path / "grid.toml"
    path.write_text("# notes\n" * 12_000 + _GRID_TOML, encoding="utf-8")  # ~96 KB
    assert 64 * 2**10 < path.stat().st_size < 64 * 2**20
    with pytest.raises(LogFormatError, match=r"is a closedloop sweep grid"):
        load(path)
