"""Round 18 PART b M04: a byte-identical copy's error row names its own file.

Reference: the input paths themselves. Three byte-identical empty files share one task
(analysed once); before the fix the rows of zero.h5 and zero.npz said
"'.../zero.csv' is empty", naming another file. Each row's message must name the row's
path and no other input.
"""

from modalinfo.batch.archive import _labelled


def test_copy_row_error_names_its_own_path():
    stored = {"path": "/d/zero.csv", "analysis": "summary", "status": "error",
              "error_type": "LogFormatError", "error_message": "'/d/zero.csv' is empty"}
    for own in ("/d/zero.h5", "/d/zero.npz"):
        row = _labelled(stored, {"path": own, "analysis": "summary"})
        assert row["path"] == own
        assert row["error_message"] == f"'{own}' is empty"
        assert "zero.csv" not in row["error_message"]
    same = _labelled(stored, {"path": "/d/zero.csv", "analysis": "summary"})
    assert same == stored
    ok = _labelled({"path": "/d/a.npz", "status": "ok", "error_message": None},
                   {"path": "/d/b.npz"})
    assert ok["path"] == "/d/b.npz" and ok["error_message"] is None
