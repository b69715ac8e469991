"""What the figure scripts share (``paper_figures/_common.py``), checked on its own.

Written for mutation testing (issue 26 item 3, docs/MUTATION.md). References, all
outside the module:

- the docstrings' contracts: an output folder and its missing parents are created at
  the end, staged in a temporary sibling in the nearest existing folder and moved in all
  or nothing; the lock ``<out>/.lock`` names the command; a log too short for a figure's
  frame needs (``MIN_FRAMES``) or with a constant
  mode is refused naming the rule and the value, a FIFO given as the log is named as
  one; ``suffixed("fig1.png", "_x")`` is ``fig1_x.png``;
- the common brief's command-line rules (one line on stderr, exit 2 for a refusal, 1
  for a failure of the work, 130 for Ctrl-C, no file overwritten unasked) and
  :mod:`modalinfo.common.cli`'s exit statuses;
- the files read back: the PNG's size in pixels is the figure's size in inches x
  110 dpi (read by matplotlib's image reader), the PDF starts with ``%PDF``, the lock
  file is JSON (read by :mod:`json`), the Markdown table parsed by Python-Markdown's
  ``tables`` extension and :mod:`html.parser`.
~2 s.
"""

from __future__ import annotations

import json
import os
import types
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pytest

from modalinfo.common.folders import OutputInUseError
from modalinfo.telemetry import ModalLog
from paper_figures import _common as c

# messages start with the program typed, as argparse's do ("fig9: error: " before fixes
# 45-c, round 44 PART b c08)
PROG = "python -m paper_figures.fig9_an_example"


# ---------------------------------------------------------------- output folders


def test_check_out_dir_returns_the_nearest_existing_folder(tmp_path):
    assert c.check_out_dir(tmp_path / "a" / "b" / "c") == tmp_path
    assert c.check_out_dir(tmp_path) == tmp_path
    (tmp_path / "f").write_text("x")
    with pytest.raises(c.OutputError) as err:
        c.check_out_dir(tmp_path / "f")
    assert str(err.value) == f"--out '{tmp_path / 'f'}' exists and is not a directory"
    with pytest.raises(c.OutputError, match=r"^--log-dir '"):
        c.check_out_dir(tmp_path / "f" / "g", "--log-dir")


def test_locked_output_names_the_run_and_refuses_a_second(tmp_path):
    out = tmp_path / "a" / "b"
    with c.locked_output(out) as held:
        assert held == out and out.is_dir()
        lock = json.loads((out / ".lock").read_text(encoding="utf-8"))
        assert lock["command"] == "paper_figures"
        with pytest.raises(OutputInUseError) as err, c.locked_output(out):
            pass
        assert str(err.value).startswith(f"--out output directory '{out}' is in use by "
                                         "paper_figures (pid ")
        with pytest.raises(OutputInUseError, match=r"^--dest output directory"), \
                c.locked_output(out, "--dest"):
            pass
    assert not (tmp_path / "a").exists()   # the folders made here were left empty


def test_locked_output_takes_a_folder_of_other_files(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    with c.locked_output(tmp_path) as held:   # a figure folder has no "rows" marker
        assert held == tmp_path
    assert (tmp_path / "notes.txt").read_text() == "mine"
    assert not (tmp_path / ".lock").exists()


def test_staged_output_creates_a_new_folder_with_its_parents(tmp_path):
    out = tmp_path / "new" / "deeper"
    with c.staged_output(out) as stage:
        assert stage.parent == tmp_path               # the nearest existing folder
        assert stage.name.startswith(".deeper.partial-")
        assert not out.exists()
        (stage / "fig.png").write_text("png")
        (stage / "sub").mkdir()
        (stage / "sub" / "a.txt").write_text("a")
    assert (out / "fig.png").read_text() == "png"
    assert (out / "sub" / "a.txt").read_text() == "a"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["new"]


def test_staged_output_into_an_existing_folder(tmp_path):
    out = tmp_path / "out"
    (out / "sub").mkdir(parents=True)
    (out / "keep.txt").write_text("keep")
    (out / "fig.png").write_text("old")
    (out / "sub" / "old.txt").write_text("old")
    with c.staged_output(out) as stage:
        assert stage.parent == out
        (stage / "fig.png").write_text("new")
        (stage / "sub").mkdir()
        (stage / "sub" / "new.txt").write_text("new")
    assert (out / "fig.png").read_text() == "new"
    assert (out / "keep.txt").read_text() == "keep"
    assert (out / "sub" / "old.txt").read_text() == "old"
    assert (out / "sub" / "new.txt").read_text() == "new"
    assert sorted(p.name for p in out.iterdir()) == ["fig.png", "keep.txt", "sub"]


def test_staged_output_of_the_current_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with c.staged_output(Path(".")) as stage:
        assert stage.name.startswith(".out.partial-")   # "." has no name
        (stage / "a.txt").write_text("a")
    assert (tmp_path / "a.txt").read_text() == "a"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]


@pytest.mark.parametrize("kind", ["file", "folder"])
def test_staged_output_refuses_a_clash_and_moves_nothing(tmp_path, kind):
    out = tmp_path / "out"
    out.mkdir()
    if kind == "file":      # the run writes a file where a folder is
        (out / "b").mkdir()
    else:                   # the run writes a folder where a file is
        (out / "b").write_text("mine")
    with pytest.raises(c.OutputError) as err, c.staged_output(out) as stage:
        (stage / "a.txt").write_text("a")      # sorted before the clash
        if kind == "file":
            (stage / "b").write_text("new")
        else:
            (stage / "b").mkdir()
    assert str(err.value) == f"'{out / 'b'}' is in the way: the run writes a {kind} there"
    assert sorted(p.name for p in out.iterdir()) == ["b"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_staged_output_leaves_nothing_when_the_block_fails(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "fig.png").write_text("old")
    with pytest.raises(KeyboardInterrupt), c.staged_output(out) as stage:
        (stage / "fig.png").write_text("new")
        raise KeyboardInterrupt
    assert (out / "fig.png").read_text() == "old"
    assert sorted(p.name for p in out.iterdir()) == ["fig.png"]
    with pytest.raises(ValueError), c.staged_output(tmp_path / "fresh") as stage:
        raise ValueError("x")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


# ---------------------------------------------------------------- logs


def log(x):
    return ModalLog(np.asarray(x, dtype=float), rate=100.0, units="waves")


def varying(n_frames, n_modes=2):
    t = np.arange(n_frames, dtype=float)
    return log(np.column_stack([np.cos(t * (k + 1)) for k in range(n_modes)]))


def test_check_log_for_uses_the_modules_own_check_first():
    seen = []
    module = types.SimpleNamespace(check_log=seen.append, MIN_FRAMES=10**9)
    flat = log(np.zeros((5, 2)))           # neither the frames nor the modes are checked
    assert c.check_log_for(module, flat) is None
    assert seen == [flat]


def test_check_log_for_min_frames_at_its_boundary():
    module = types.SimpleNamespace(MIN_FRAMES=12)
    c.check_log_for(module, varying(12))
    with pytest.raises(ValueError) as err:
        c.check_log_for(module, varying(11))
    assert str(err.value) == "`log` must hold at least 12 frames; got 11."


def test_check_log_for_fig5_uses_its_min_frames():
    # Figure 5's need is its own MIN_FRAMES (panel (c) measures up to frame NN_END + 60),
    # beyond the ARMA windows' N_FIT + 2 H_ARMA; a module's N_FIT / H_ARMA alone are no rule
    from paper_figures import fig5_forecast as fig5
    assert fig5.MIN_FRAMES == fig5.NN_END + 61 > fig5.N_FIT + 2 * fig5.H_ARMA
    c.check_log_for(types.SimpleNamespace(N_FIT=10, H_ARMA=3), varying(3))

def test_check_log_for_refuses_a_constant_mode():
    x = np.column_stack([np.arange(6.0), np.full(6, 2.0)])
    with pytest.raises(ValueError) as err:
        c.check_log_for(types.SimpleNamespace(), log(x))
    label = log(x).labels[1]
    assert str(err.value) == (f"`log` must have modes that vary: 1 mode(s) do not vary, the "
                              f"first {label}; the figure's statistics are 0/0 otherwise.")


def test_require_varying_modes_names_the_first_constant_mode():
    x = np.column_stack([np.arange(6.0), np.full(6, 2.0), np.arange(6.0) ** 2, np.ones(6)])
    with pytest.raises(ValueError) as err:
        c.require_varying_modes(log(x), "S")
    assert str(err.value) == (f"`log` must have modes that vary: 2 mode(s) do not vary, "
                              f"the first {log(x).labels[1]}; S are 0/0 otherwise.")
    with pytest.raises(ValueError) as err:
        c.require_varying_modes(log(np.zeros((4, 3))), "S")
    assert str(err.value) == ("`log` must have modes that vary: every mode is constant (an "
                              "all-zero log?); S are 0/0 otherwise.")
    # a mode varying by one part in 2^40 varies
    c.require_varying_modes(log([[1.0, 0.0], [1.0 + 2.0**-40, 1.0]]), "S")
    assert c.require_varying_modes(varying(3), "S") is None


def test_log_or_kaos_like(tmp_path, monkeypatch):
    import modalinfo.io
    import modalinfo.telemetry.synthetic as synthetic

    calls = []
    monkeypatch.setattr(synthetic, "kaos_like", lambda **kw: calls.append(kw) or "kaos")
    monkeypatch.setattr(modalinfo.io, "load", lambda p: calls.append(p) or "file")
    assert c.log_or_kaos_like(None) == (
        "kaos", "synthetic `kaos_like(seed=0)` (closed loop, not real data)")
    path = tmp_path / "my.fits"
    assert c.log_or_kaos_like(path) == ("file", f"`{path}`")
    assert calls == [{"seed": 0}, path]


# ---------------------------------------------------------------- report pieces


class _Cells(HTMLParser):
    """The header and body cells of the HTML tables, row by row."""

    def __init__(self):
        super().__init__()
        self.rows, self.cell = [], None

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self.rows.append([])
        elif tag in ("th", "td"):
            self.cell = (tag, "")

    def handle_data(self, data):
        if self.cell is not None:
            self.cell = (self.cell[0], self.cell[1] + data)

    def handle_endtag(self, tag):
        if tag in ("th", "td"):
            self.rows[-1].append(self.cell)
            self.cell = None


def cells(md):
    import markdown

    p = _Cells()
    p.feed(markdown.markdown(md, extensions=["tables"]))
    return p.rows


def test_markdown_table_of_four_columns():
    md = c.markdown_table([("SR", "0.4", "0.5", "a shorter run"), ("n", "20", "18", "-")])
    assert cells(md) == [
        [("th", "quantity"), ("th", "paper"), ("th", "ours"), ("th", "why they differ")],
        [("td", "SR"), ("td", "0.4"), ("td", "0.5"), ("td", "a shorter run")],
        [("td", "n"), ("td", "20"), ("td", "18"), ("td", "-")]]
    assert md.count("\n") == 3


def test_markdown_table_of_three_columns():
    md = c.markdown_table([("SR", "0.4", "0.5"), ("n", "20", "18", "x", "y")])
    assert cells(md) == [[("th", "quantity"), ("th", "paper"), ("th", "ours")],
                         [("td", "SR"), ("td", "0.4"), ("td", "0.5")],
                         [("td", "n"), ("td", "20"), ("td", "18")]]
    assert md.count("\n") == 3
    assert c.markdown_table([]) == "| quantity | paper | ours |\n|---|---|---|"


def test_suffixed():
    assert c.suffixed("fig1.png", "_x") == "fig1_x.png"
    assert c.suffixed("a.b.pdf", "-2") == "a.b-2.pdf"
    assert c.suffixed("fig1.png", "") == "fig1.png"


def test_save_png_pdf_at_110_dpi(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.image as mpimg
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(2.0, 1.0))
    paths = c.save_png_pdf(fig, str(tmp_path), "a.png", "b.pdf")
    assert paths == [tmp_path / "a.png", tmp_path / "b.pdf"]
    assert mpimg.imread(paths[0]).shape[:2] == (110, 220)
    assert paths[1].read_bytes().startswith(b"%PDF")
    assert not plt.fignum_exists(fig.number)
    # the figure saved is closed, not the current one
    fig = plt.figure(figsize=(1.0, 1.0))
    other = plt.figure(figsize=(1.0, 1.0))
    c.save_png_pdf(fig, tmp_path, "c.png", "d.pdf")
    assert not plt.fignum_exists(fig.number) and plt.fignum_exists(other.number)
    plt.close(other)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png", "b.pdf", "c.png", "d.pdf"]


# ---------------------------------------------------------------- figure_main


def maker(calls, text="the report", files=("fig.png",), error=None):
    def make(stage, log_path, **kw):
        calls.append((stage, log_path, kw))
        for name in files:
            (stage / name).write_text("data")
        if error is not None:
            raise error
        return text
    return make


def run(argv, make, output_names=None, figure_name="fig.png", prog=PROG):
    return c.figure_main(argv, prog=prog, description="Draws the example figure.",
                         figure_name=figure_name, make=make, output_names=output_names)


def names(suffix):
    return [c.suffixed("fig.png", suffix), c.suffixed("fig.pdf", suffix)]


def test_figure_main_draws_and_prints(tmp_path, capsys):
    calls = []
    out = tmp_path / "o"
    assert run(["--out", str(out)], maker(calls)) == 0
    assert capsys.readouterr() == ("the report\n", "")
    assert (out / "fig.png").read_text() == "data"
    [(stage, log_path, kw)] = calls
    assert log_path is None and kw == {} and stage != out
    logf = tmp_path / "my.log"
    logf.write_text("x")
    assert run(["--out", str(out), "--log", str(logf), "--overwrite"], maker(calls)) == 0
    assert calls[-1][1:] == (logf, {})


def test_figure_main_default_out(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert run([], maker([])) == 0
    assert (tmp_path / "out" / "fig.png").is_file()


def test_figure_main_with_a_suffix(tmp_path, capsys):
    calls = []
    out = tmp_path / "o"
    make = maker(calls, files=("fig_s.png", "fig_s.pdf"))
    assert run(["--out", str(out), "--suffix", "_s"], make, names) == 0
    assert calls[-1][2] == {"suffix": "_s"}
    assert sorted(p.name for p in out.iterdir()) == ["fig_s.pdf", "fig_s.png"]
    assert run(["--out", str(out)], maker(calls), names) == 0     # the default suffix: ""
    assert calls[-1][2] == {"suffix": ""}
    logf = tmp_path / "my.log"
    logf.write_text("x")
    make = maker(calls, files=("fig_XL.png",))
    assert run(["--out", str(out), "--suffix", "_XL", "--log", str(logf)], make, names) == 0
    assert calls[-1][1:] == (logf, {"suffix": "_XL"})
    capsys.readouterr()
    # the PDF alone exists: still refused (every listed file is checked)
    (out / "fig_s.png").unlink()
    assert run(["--out", str(out), "--suffix", "_s"], maker(calls), names) == 2
    assert capsys.readouterr().err == (
        f"{PROG}: error: '{out / 'fig_s.pdf'}' exists; pass --overwrite\n")


@pytest.mark.parametrize("suffix", ["a/b", "a\\b", "a\0b"])
def test_figure_main_refuses_a_suffix_with_a_separator(tmp_path, capsys, suffix):
    calls = []
    assert run(["--out", str(tmp_path), "--suffix", suffix], maker(calls), names) == 2
    assert capsys.readouterr() == (
        "", f"{PROG}: error: --suffix must not contain a path separator; got {suffix!r}\n")
    assert calls == []


@pytest.mark.parametrize("prog", [
    "python3.12 -m paper_figures.fig9_an_example", "fig9_tool",
    "python -m paper_figures.fig1_fitting_error"])
def test_figure_main_names_the_figure_in_its_messages(tmp_path, capsys, prog):
    # the program as typed, the name argparse's refusals carry (fixes 45-c, c08)
    (tmp_path / "fig.png").write_text("mine")
    assert run(["--out", str(tmp_path)], maker([]), prog=prog) == 2
    assert capsys.readouterr().err.startswith(f"{prog}: error: '")


def test_figure_main_without_output_names_has_no_suffix(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        run(["--out", str(tmp_path), "--suffix", "_s"], maker([]))
    assert exc.value.code == 2


def test_figure_main_refuses_to_overwrite(tmp_path, capsys):
    (tmp_path / "fig.png").write_text("mine")
    calls = []
    assert run(["--out", str(tmp_path)], maker(calls)) == 2
    assert capsys.readouterr() == (
        "", f"{PROG}: error: '{tmp_path / 'fig.png'}' exists; pass --overwrite\n")
    assert calls == [] and (tmp_path / "fig.png").read_text() == "mine"
    assert run(["--out", str(tmp_path), "--overwrite"], maker(calls)) == 0
    assert (tmp_path / "fig.png").read_text() == "data"


def test_figure_main_refuses_bad_places(tmp_path, capsys):
    calls = []
    (tmp_path / "file").write_text("x")
    assert run(["--out", str(tmp_path / "file")], maker(calls)) == 2
    assert capsys.readouterr().err == (
        f"{PROG}: error: --out '{tmp_path / 'file'}' exists and is not a directory\n")
    assert run(["--out", str(tmp_path / "o"), "--log", str(tmp_path)], maker(calls)) == 2
    assert capsys.readouterr().err == (
        f"{PROG}: error: --log '{tmp_path}' is a folder, not a log file\n")
    missing = tmp_path / "missing.fits"
    assert run(["--out", str(tmp_path / "o"), "--log", str(missing)], maker(calls)) == 2
    assert capsys.readouterr().err == f"{PROG}: error: log file '{missing}' does not exist\n"
    assert calls == [] and not (tmp_path / "o").exists()


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes on this system")
def test_figure_main_names_a_fifo_given_as_the_log(tmp_path, capsys):
    # a named pipe exists but is not a regular file: one line naming it as such (exit 2),
    # not "does not exist", and nothing read or written (the FIFO is not opened)
    calls = []
    pipe = tmp_path / "pipe.npz"
    os.mkfifo(pipe)
    assert run(["--out", str(tmp_path / "o"), "--log", str(pipe)], maker(calls)) == 2
    assert capsys.readouterr().err == (
        f"{PROG}: error: --log '{pipe}' is not a regular file (a FIFO or a device)\n")
    assert calls == [] and not (tmp_path / "o").exists()


@pytest.mark.parametrize("error, code, message", [
    (ValueError("first line\nsecond line"), 2, "first line"),
    (TypeError("  typed  \n"), 2, "typed"),
    (ValueError(""), 2, "ValueError('')"),
    (ValueError("  "), 2, "ValueError('  ')"),
    # a full disk names the --out folder (left13-cli: files.naming_target)
    (OSError(28, "No space left on device"), 1,
     "No space left on device writing '{out}' (nothing was written); free space or write "
     "elsewhere"),
    (MemoryError("big"), 1, "MemoryError: big; nothing was written"),
    (KeyboardInterrupt(), 130, "interrupted; nothing was written"),
])
def test_figure_main_failures_in_one_line(tmp_path, capsys, error, code, message):
    out = tmp_path / "o"
    assert run(["--out", str(out)], maker([], error=error)) == code
    assert capsys.readouterr() == ("", f"{PROG}: error: {message.format(out=out)}\n")
    assert not out.exists()                     # nothing was written
    assert sorted(p.name for p in tmp_path.iterdir()) == []


def test_figure_main_help(capsys):
    with pytest.raises(SystemExit) as exc:
        run(["--help"], maker([]), names)
    assert exc.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    assert text.startswith(f"usage: {PROG} ")
    for words in ("Draws the example figure.",
                  "--log LOG modal log (default: synthetic kaos_like(seed=0))",
                  "--out OUT output directory",
                  "--overwrite replace an existing figure",
                  "--suffix SUFFIX inserted before the extension of every output file name"):
        assert words in text
