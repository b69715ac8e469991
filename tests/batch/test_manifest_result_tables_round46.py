"""A result table given to batch as its input is named, not read as a manifest.

Round 46 PART b (hidden adversary, the command lines): `modalinfo batch b1/batch.csv`
read batch.csv as a manifest, "unknown column 'analysis'" (F31), and `batch sw/sweep.csv`
was told to "name the file column 'path'", which would only feed closedloop results to
batch (G10). Reference: the header each program writes (modalinfo batch's batch.csv,
closedloop sweep's sweep.csv, modalinfo forecast's forecast.csv).
"""

from __future__ import annotations

import pytest

from modalinfo.batch.manifest import collect_logs

_HEADERS = {
    "batch.csv": ('"path","analysis","status","sha256","version"\n'
                  '"/data/a.npz","summary","ok","ab","0.1.0"\n',
                  "batch.csv, the result table of `modalinfo batch`"),
    "sweep.csv": ('"override","seed","predictor","status","result_file"\n'
                  '"base",0,"none","ok","/runs/k.h5"\n',
                  "sweep.csv, the result table of `closedloop sweep`"),
    "forecast.csv": ("predictor,mode,horizon,rmse,gain\npersistence,wavefront,1,0.1,1.0\n",
                     "forecast.csv, the table of `modalinfo forecast --out`"),
}


@pytest.mark.parametrize("name", sorted(_HEADERS))
def test_result_table_as_input_named(tmp_path, name):
    text, what = _HEADERS[name]
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    with pytest.raises(ValueError) as info:
        collect_logs([path])
    message = str(info.value)
    assert f"is {what}, not a log or a manifest" in message
    assert "unknown column" not in message and "name the file column" not in message


def test_manifest_path_relative_to_the_current_folder_named(tmp_path, monkeypatch):
    """A manifest's relative paths are read from its folder (manifest.py's docstring).

    A row written relative to the current folder was an error row "no such file:
    '<manifest folder>/arch/a.npz'" after the run (round 46 PART b, R02).
    """
    (tmp_path / "arch").mkdir()
    (tmp_path / "arch" / "a.npz").write_bytes(b"PK\x05\x06" + bytes(18))
    (tmp_path / "man").mkdir()
    manifest = tmp_path / "man" / "m.csv"
    manifest.write_text("path\narch/a.npz\n", encoding="utf-8")
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match=r"row 2: 'arch/a.npz' is not in the manifest's "
                                         r"folder .*, from which its relative paths are "
                                         r"read, but in the current folder"):
        collect_logs([manifest])
