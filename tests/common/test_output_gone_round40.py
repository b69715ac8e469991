"""An output folder renamed while a batch writes its rows: said so, exit status 1.

Round 40 PART b F38b: ``mv out moved`` after the first row of ``modalinfo batch ... --out
out`` ended in "modalinfo batch: error: directory 'out/rows' does not exist (writing
'out/rows/<key>.json')", status 2 - the README's status of an input error found before
any work - and no word that the folder went away during the run, nor where the finished
row is. Reference: the file system itself (``os.rename`` of the folder; the row written
before is read back from its new place with ``json``) and the README's exit statuses
(1: the run failed after it started; 2: an input error before any work).
"""

import argparse
import json

import pytest

from modalinfo.common.cli import dispatch
from modalinfo.common.tasks.rows import RowStore


def test_a_row_store_whose_folder_was_renamed_says_so(tmp_path):
    store = RowStore(tmp_path / "out")
    store.write("first", {"status": "ok", "value": 1.0})
    (tmp_path / "out").rename(tmp_path / "moved")
    with pytest.raises(OSError) as caught:
        store.write("second", {"status": "ok", "value": 2.0})
    message = str(caught.value)
    assert f"output directory '{tmp_path / 'out'}' was removed or renamed" in message
    assert "--out at its new place to resume" in message
    kept = json.loads((tmp_path / "moved" / "rows" / "first.json").read_text())
    assert kept["value"] == 1.0 and not (tmp_path / "out").exists()


def test_dispatch_gives_status_1_and_one_line(tmp_path, capsys):
    def run(args):
        store = RowStore(tmp_path / "out")
        (tmp_path / "out").rename(tmp_path / "moved")
        store.write("k", {"status": "ok"})

    parser = argparse.ArgumentParser(prog="prog")
    sub = parser.add_subparsers(dest="command")
    sub.add_parser("go").set_defaults(_run=run)
    assert dispatch(parser, ["go"], "prog") == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert err.startswith("prog go: error: output directory") and "renamed" in err, err
