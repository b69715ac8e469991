"""Result tables given to ``batch`` are named whatever the case of their suffix (review29).

Round 29 N3 (modalinfo/batch/manifest.py:450, round 46 PART b F31 / G10): an input file
that is a result table (``result_table``: its first line) is refused by name. Planted to
judge only names ending in ``.csv``, it passed every test: ``FORECAST.CSV`` (a copy from
a case-insensitive disk) went to the manifest reader, "unknown column". Reference,
outside the package: the round 46 texts, and the forecast table's header written here
as ``modalinfo forecast --out`` writes it (predictor,mode,horizon,...).
"""

import pytest

from modalinfo.batch.manifest import collect_logs


@pytest.mark.parametrize("name", ["FORECAST.CSV", "forecast.csv"])
def test_a_forecast_table_is_named_whatever_its_suffix_case(tmp_path, name):
    path = tmp_path / name
    path.write_text("predictor,mode,horizon,rmse\npersistence,Z2,1,0.1\n", encoding="utf-8")
    with pytest.raises(ValueError, match=r"is forecast\.csv, the table of `modalinfo "
                                         r"forecast --out`, not a log or a manifest"):
        collect_logs(path)
