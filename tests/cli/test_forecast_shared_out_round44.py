"""``forecast --out`` shared by two processes: the one refused keeps the other's outputs.

Round 44 PART b, d08. Two ``modalinfo forecast ... --out DIR`` started on a folder that did
not exist yet: the slower one (A) saw no folder, created it and staged its files; the
faster one (B) wrote its four outputs there and said "wrote ..."; A then found
``forecast.json`` existing, refused ("pass --overwrite"), and removed the whole folder it
believed it had created (``shutil.rmtree(out)``): B's outputs were lost. Reference: the
README's promise that a failed write leaves "the old file or none" and B's own success
message; the other process is played here by the stub's ``save_plots``, which writes B's
files while A stages (as the race did with ``python -m modalinfo`` twice).
"""
from pathlib import Path

import pytest

from modalinfo.cli import CommandError
from modalinfo.cli.cmd_forecast import OUTPUTS, write_outputs


class _Evaluation:
    """What write_outputs needs of a ForecastEvaluation; plotting lets B finish first."""

    def __init__(self, out: Path):
        self.out = out

    def to_json(self, path, provenance=None, quality=None):
        Path(path).write_text("{}")

    def to_csv(self, path, provenance=None, quality=None):
        Path(path).write_text("predictor\n")

    def save_plots(self, folder, provenance=None):
        for name in OUTPUTS[2:]:
            (Path(folder) / name).write_bytes(b"A")
        for name in OUTPUTS:  # the other process's run ends now, in the same --out
            (self.out / name).write_text("B's " + name)


def test_refused_run_keeps_the_other_process_outputs(tmp_path):
    out = tmp_path / "fc"  # absent: both runs see a folder to create
    with pytest.raises(CommandError, match="exists; pass --overwrite"):
        write_outputs(_Evaluation(out), out, overwrite=False)
    assert sorted(p.name for p in out.iterdir()) == sorted(OUTPUTS)
    for name in OUTPUTS:
        assert (out / name).read_text() == "B's " + name


def test_refused_run_alone_still_removes_the_folder_it_made(tmp_path):
    """The rollback the rmtree served: a failure with nothing else there leaves no folder."""

    class Failing(_Evaluation):
        def save_plots(self, folder, provenance=None):
            raise OSError("disk full")

    out = tmp_path / "fc"
    with pytest.raises(OSError, match="disk full"):
        write_outputs(Failing(out), out, overwrite=False)
    assert not out.exists()
