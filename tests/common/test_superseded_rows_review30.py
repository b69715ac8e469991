"""``superseded_rows`` counts rows under other keys, not the current ones (review30 R2).

test_superseded_rows_round47.py's folder holds as many current rows (2) as superseded
ones (2), so a planted ``row.get("key") in keys`` (counting the current rows) gave the
same 2 and passed. Reference: row files written here by hand, counted by eye: one
current row, three of the same entry under older keys.
"""

import json

from modalinfo.common.tasks.rows import superseded_rows


def test_current_rows_are_not_counted(tmp_path):
    rows_dir = tmp_path / "rows"
    rows_dir.mkdir()
    base = {"sha256": "a" * 64, "analysis": "summary", "window": 0}
    now = [{"key": "k", **base}]
    for key in ("k", "o1", "o2", "o3"):
        (rows_dir / f"{key}.json").write_text(json.dumps({"key": key, **base}))
    assert superseded_rows(rows_dir, now, ("sha256", "analysis", "window")) == 3
