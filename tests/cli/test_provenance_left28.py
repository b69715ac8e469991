"""left28-prov (issue 27): forecast.csv and paper_figures' PNG / PDF record what made them.

docs/ADVERSARIAL.md, "Round 27 PART b, issue 27", rows P08 (forecast.csv: no record of
version, command or input) and the paper_figures figures ("Leftovers 27-geometry",
Left: their PNG / PDF named neither the code nor the inputs).

References, all outside the code that writes the record: ``hashlib.sha256`` of the
input files' bytes; ``modalinfo.__version__``; the command line as the test typed it
(``shlex.split`` of the CSV cell); the CSV read by ``csv.DictReader`` and
``pandas.read_csv`` with no option (the readers the table is for); the PNG text chunks
as Pillow reads them; the PDF's Info dictionary parsed here from the file's bytes (the
PDF literal-string escapes of ISO 32000-1, 7.3.4.2); ``git rev-parse`` for the commit.
Byte-reproducibility: the same figure saved twice gives the same bytes.
"""

from __future__ import annotations

import csv
import hashlib
import json
import re
import shlex
import shutil
import subprocess
from pathlib import Path

import pandas as pd
import pytest
from PIL import Image

import modalinfo

from .conftest import exit_code


def _pdf_info(path: Path) -> dict[str, str]:
    """The literal-string entries of the PDF's Info dictionary (the one with /Producer)."""
    data = path.read_bytes()
    start = data.rfind(b"/Producer")
    assert start > 0
    begin, end = data.rfind(b"<<", 0, start), data.find(b">>", start)
    body = data[begin + 2:end]
    out, i = {}, 0
    while (m := re.compile(rb"/(\w+)\s*\(").search(body, i)) is not None:
        j, depth, chars = m.end(), 1, bytearray()
        while True:  # a literal string: \-escapes, balanced parentheses
            c = body[j:j + 1]
            if c == b"\\":
                nxt = body[j + 1:j + 2]
                chars += {b"n": b"\n", b"r": b"\r", b"t": b"\t"}.get(nxt, nxt)
                j += 2
                continue
            if c == b"(":
                depth += 1
            elif c == b")":
                depth -= 1
                if depth == 0:
                    break
            chars += c
            j += 1
        out[m.group(1).decode()] = chars.decode("latin-1")
        i = j + 1
    return out


# ------------------------------------------------------------------ P08: forecast.csv
def test_forecast_csv_carries_the_record_and_reads_as_before(make_small_log, tmp_path,
                                                              capsys):
    log = make_small_log(400)
    out = tmp_path / "fc"
    argv = ["forecast", str(log), "--modes", "2,3", "--predictors", "linear", "--horizon",
            "2", "--out", str(out), "--quiet"]
    assert exit_code(argv) == 0, capsys.readouterr().err
    with open(out / "forecast.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    table = pd.read_csv(out / "forecast.csv")  # no comment= needed: a plain table
    assert len(rows) == len(table) > 0
    assert list(table.columns[:9]) == ["predictor", "mode", "horizon", "rmse", "gain",
                                       "coverage", "dm_statistic", "p_value",
                                       "beats_baseline"]
    sha = hashlib.sha256(log.read_bytes()).hexdigest()
    for row in rows:
        assert row["input_sha256"] == sha
        assert row["modalinfo"].startswith(modalinfo.__version__ + "+src.")
        assert shlex.split(row["command"])[1:] == argv
    # the same record as forecast.json beside it
    record = json.loads((out / "forecast.json").read_text())["provenance"]
    assert rows[0]["modalinfo"] == record["modalinfo"]
    # left30-prov: the commit (marked -dirty if edited) and the source's SHA-256 too
    assert rows[0]["git"] == (record["git"] or "")
    assert rows[0]["source_sha256"] == record["source_sha256"]
    assert re.fullmatch(r"[0-9a-f]{64}", rows[0]["source_sha256"])
    assert table["horizon"].dtype.kind == "i" and table["rmse"].notna().all()


def test_forecast_csv_without_a_record_keeps_its_nine_columns(tmp_path):
    import numpy as np

    from modalinfo.forecast import LinearPredictor, evaluate
    from modalinfo.telemetry import ModalLog

    rng = np.random.default_rng(0)
    log = ModalLog(rng.standard_normal((400, 2)).cumsum(0) * 0.01, rate=1000.0,
                   modes=[2, 3], units="rad")
    ev = evaluate([LinearPredictor()], log, train=200, horizons=[1])
    plain = ev.to_csv(tmp_path / "a.csv").read_text().splitlines()
    made = ev.to_csv(tmp_path / "b.csv", provenance={
        "modalinfo": "v", "command": ["modalinfo", "x y"], "input": {"sha256": "ab"}},
    ).read_text().splitlines()
    # the nine columns, then (round 43 PART a, U11) the units of rmse last
    assert plain[0].split(",") == ["predictor", "mode", "horizon", "rmse", "gain",
                                   "coverage", "dm_statistic", "p_value", "beats_baseline",
                                   "units"]
    assert len(plain) == len(made)
    for a, b in zip(plain, made, strict=True):  # the same cells, five more before units
        nine, units = a.rsplit(",", 1)
        assert b.startswith(nine + ",") and b.endswith("," + units)
    # a record without git / source_sha256 (left30-prov's columns): empty cells
    assert made[1].endswith(",v,ab,modalinfo 'x y',,,rad")


# ------------------------------------------------------------------ paper_figures
def _tiny_figure():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(2, 2))
    ax.plot([0, 1], [1, 0])
    return fig


def test_save_png_pdf_writes_the_record_in_both_and_no_date(tmp_path):
    from paper_figures._common import figure_record, save_png_pdf

    record = {"modalinfo": "0.1.0+src.abc", "command": ["paper_figures", "--out", "a (b)"],
              "input": None, "seed": 3}
    paths = []
    for name in ("one", "two"):
        (tmp_path / name).mkdir()
        with figure_record(record):
            paths.append(save_png_pdf(_tiny_figure(), tmp_path / name, "f.png", "f.pdf"))
    (png, pdf), (png2, pdf2) = paths
    with Image.open(png) as im:
        assert json.loads(im.text["Description"]) == record
    info = _pdf_info(pdf)
    assert json.loads(info["Subject"]) == record
    assert info["Title"] == "f" and info["Creator"] == "modalinfo 0.1.0+src.abc"
    assert b"/CreationDate" not in pdf.read_bytes()
    # no time of day anywhere: the same figure is the same bytes
    assert png.read_bytes() == png2.read_bytes() and pdf.read_bytes() == pdf2.read_bytes()
    # outside figure_record: no record, still no date
    (tmp_path / "bare").mkdir()
    bare_png, bare_pdf = save_png_pdf(_tiny_figure(), tmp_path / "bare", "f.png", "f.pdf")
    with Image.open(bare_png) as im:
        assert "Description" not in im.text
    assert "Subject" not in _pdf_info(bare_pdf)
    assert b"/CreationDate" not in bare_pdf.read_bytes()


class _OwnFigure:
    """A figure of its own (kind "own", as Figure 6) drawn through save_png_pdf."""

    NEEDS_LOG = False
    FIGURE_NAME, PDF_NAME, JSON_NAME = "f6.png", "f6.pdf", "f6.json"

    def compute(self, *, quick, seed):
        return "r"

    def plot(self, result, out_dir):
        from paper_figures._common import save_png_pdf

        (out_dir / self.JSON_NAME).write_text("{}")
        return save_png_pdf(_tiny_figure(), out_dir, self.FIGURE_NAME, self.PDF_NAME)

    def report(self, result):
        return "## Figure 6: about r\n"

    def table_rows(self, result):
        return []


def test_paper_figures_main_records_version_command_seed_and_inputs(monkeypatch, tmp_path):
    import importlib

    from paper_figures.__main__ import main

    real_import = importlib.import_module
    own = _OwnFigure()
    monkeypatch.setattr("paper_figures.__main__.importlib.import_module",
                        lambda name, *a: own if name.endswith("fig6_compression")
                        else real_import(name, *a))
    out = tmp_path / "out"
    argv = ["--only", "6", "--quick", "--seed", "4", "--out", str(out)]
    assert main(argv) == 0
    with Image.open(out / "f6.png") as im:
        record = json.loads(im.text["Description"])
    assert json.loads(_pdf_info(out / "f6.pdf")["Subject"]) == record
    assert record["modalinfo"].startswith(modalinfo.__version__ + "+src.")
    assert record["command"][1:] == argv and record["seed"] == 4
    assert "inputs" not in record  # Figure 6 reads no log
    assert record["modalinfo"] in (out / "report.md").read_text().splitlines()[2]


def test_stand_alone_figure_records_its_log(make_small_log, tmp_path):
    from paper_figures._common import figure_main, save_png_pdf

    log = make_small_log(100)

    def make(stage, log_path):
        save_png_pdf(_tiny_figure(), stage, "g.png", "g.pdf")
        return "text"

    argv = ["--log", str(log), "--out", str(tmp_path / "o")]
    assert figure_main(argv, prog="python -m paper_figures.fig9", description="d",
                       figure_name="g.png", make=make) == 0
    with Image.open(tmp_path / "o" / "g.png") as im:
        record = json.loads(im.text["Description"])
    assert record["input"]["sha256"] == hashlib.sha256(log.read_bytes()).hexdigest()
    assert record["command"] == ["python -m paper_figures.fig9", *argv]


# ------------------------------------------------------------------ git_revision
def _git(*args, cwd):
    return subprocess.run(["git", *args], cwd=cwd, check=True, capture_output=True,
                          text=True).stdout.strip()


@pytest.mark.skipif(shutil.which("git") is None, reason="needs the git command")
def test_git_revision_reads_what_git_rev_parse_prints(tmp_path):
    from modalinfo.common.provenance import git_revision

    repo = tmp_path / "repo"
    repo.mkdir()
    _git("init", "-q", "-b", "main", cwd=repo)
    for n in range(2):
        (repo / "f.txt").write_text(str(n))
        _git("add", "f.txt", cwd=repo)
        _git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", str(n),
             cwd=repo)
    assert git_revision(repo) == _git("rev-parse", "HEAD", cwd=repo)
    _git("pack-refs", "--all", cwd=repo)  # the branch only in packed-refs
    assert not (repo / ".git" / "refs" / "heads" / "main").exists()
    assert git_revision(repo) == _git("rev-parse", "HEAD", cwd=repo)
    first = _git("rev-parse", "HEAD~1", cwd=repo)
    _git("worktree", "add", "-q", "--detach", str(tmp_path / "wt"), first, cwd=repo)
    assert (tmp_path / "wt" / ".git").is_file()  # a worktree's .git names its folder
    assert git_revision(tmp_path / "wt") == first
    _git("checkout", "-q", "-b", "side", cwd=tmp_path / "wt")  # a branch of the worktree
    assert git_revision(tmp_path / "wt") == first
    assert git_revision(tmp_path) is None  # not a checkout (no search upwards)


def test_git_revision_of_the_code_is_its_checkout():
    from modalinfo.common.provenance import git_revision

    top = Path(modalinfo.__file__).resolve().parents[1]
    if shutil.which("git") is None or not (top / ".git").exists():
        pytest.skip("the code is not a git checkout here")
    assert git_revision() == _git("rev-parse", "HEAD", cwd=top)

