r"""``paper_figures --log NAME``: report.md and report.html show the name, whatever it holds.

Stop 56 left (fix49-c): the report's head and Figures 1 and 5's sections put the user's
path raw into the Markdown (`` `{path}` ``), so a newline split the head line, a ``|``
cut the comparison table's row short (GFM splits a table row at every ``|``, inside
code too), a byte that is not UTF-8 stopped the report's writing, and a ``<script>``
reached the stand-alone figure's stdout as typed.

References, outside the package: two Markdown renderers, Python-Markdown (what
report.html is made with) and markdown-it-py's CommonMark with its GFM table rule
(GitHub's reading of report.md); the text they render, HTML-unescaped, against
``codecs.escape_decode`` of it (``ls -b``'s escapes back to the file's bytes, as
tests/cli/test_report_paths_fix49c.py reads the shown form); and the rendered report of
a plain name (``plain.npz``) as the expected structure: every other name must give the
same elements (tags other than ``code``), the same table cells and the same text, the
name apart. Figures 1 and 5 are not computed: ``compute`` returns the hand-made results
of tests/paper_figures/test_mutation_gaps_fig1_fitting_error.py and
test_mutation_gaps_fig5_forecast.py with the run's ``source``; their ``report`` and
``table_rows`` are the package's. ~1 s a name.
"""

from __future__ import annotations

import codecs
import dataclasses
import html
import os
import re
from html.parser import HTMLParser
from pathlib import Path
from types import SimpleNamespace

import pytest

from modalinfo.io import save
from modalinfo.telemetry.synthetic import kaos_like
from paper_figures import __main__ as pf
from paper_figures import _common
from paper_figures import fig1_fitting_error as fig1
from paper_figures import fig5_forecast as fig5

from .test_mutation_gaps_fig1_fitting_error import _figure as _fig1_result
from .test_mutation_gaps_fig5_forecast import _figure as _fig5_result

PLAIN = b"plain"
#: the brief's names (a newline, a "|", a "<script>", emphasis stars, a byte that is not
#: UTF-8) and three that meet the code span's own syntax (a backtick, a trailing
#: backslash, a leading "|")
NAMES = [b"a\nb", b"a|b|c", b"<script>alert(1)", b"*a* _b_ **c**", b"a\xe9",
         b"a`b``c", b"ab\\", b"|a"]


class _Tree(HTMLParser):
    """The rendered elements (tags but ``code``), the table rows' cell counts and the text."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.tags, self.rows, self.text = [], [], []

    def handle_starttag(self, tag, attrs):
        if tag != "code":
            self.tags.append(tag)
        if tag == "tr":
            self.rows.append(0)
        elif tag in ("td", "th"):
            self.rows[-1] += 1

    def handle_data(self, data):
        self.text.append(data)


def _tree(rendered: str) -> SimpleNamespace:
    parser = _Tree()
    parser.feed(rendered)
    return SimpleNamespace(tags=parser.tags, rows=parser.rows, text="".join(parser.text))


def _renderers():
    import markdown
    from markdown_it import MarkdownIt

    gfm = MarkdownIt("commonmark").enable("table")
    return {"python-markdown": lambda t: markdown.markdown(t, extensions=["tables"]),
            "gfm": gfm.render}


@pytest.fixture
def stand_ins(monkeypatch):
    """Figures 1 and 5 as hand-made results with the run's source; a clock of 1 s ticks."""

    def plot(module):
        def draw(result, out_dir, *, suffix=""):
            for name in module.output_names(suffix):
                (Path(out_dir) / name).write_bytes(b"stand-in")
        return draw

    monkeypatch.setattr(fig1, "compute", lambda log, *, source, **kw: dataclasses.replace(
        _fig1_result(), source=source))
    monkeypatch.setattr(fig5, "compute", lambda log, *, source, **kw: dataclasses.replace(
        _fig5_result(), source=source))
    monkeypatch.setattr(fig1, "plot", plot(fig1))
    monkeypatch.setattr(fig5, "plot", plot(fig5))
    monkeypatch.setattr(pf, "time", SimpleNamespace(perf_counter=iter(range(100, 1000)).__next__))


@pytest.fixture(scope="module")
def log_bytes(tmp_path_factory) -> bytes:
    """One small log's file: every name holds the same bytes (the same SHA-256)."""
    path = tmp_path_factory.mktemp("log") / "log.npz"
    save(kaos_like(n_frames=7100, seed=0, modes=list(range(2, 29))), path)
    return path.read_bytes()


def _report(folder: Path, stem: bytes, data: bytes) -> tuple[bytes, str, str]:
    """Run ``paper_figures --only 1,5 --log FOLDER/logs/STEM.npz``: the path, report.md, .html."""
    (folder / "logs").mkdir(parents=True)
    path = os.path.join(os.fsencode(folder / "logs"), stem + b".npz")
    with open(path, "wb") as stream:
        stream.write(data)
    out = folder / "out"
    assert pf.main(["--out", str(out), "--only", "1,5", "--log", os.fsdecode(path)]) == 0
    return (path, (out / "report.md").read_text(encoding="utf-8"),
            (out / "report.html").read_text(encoding="utf-8"))


def _shown_in(text: str, path: bytes) -> int:
    """How many times ``text`` names ``path``: its ``ls -b`` form read back to the bytes."""
    shown = _ls_b(path)
    assert codecs.escape_decode(shown.encode())[0] == path  # the reference reads back
    return text.count(shown)


def _ls_b(path: bytes) -> str:
    r"""``ls -b``'s form of a name, written here: ``\\``, ``\n``, ``\xNN`` for a bad byte."""
    out = []
    for char in path.decode("utf-8", "surrogateescape"):
        if char == "\\":
            out.append("\\\\")
        elif char == "\n":
            out.append("\\n")
        elif "\udc80" <= char <= "\udcff":
            out.append(f"\\x{ord(char) - 0xDC00:02x}")
        else:
            out.append(char)
    return "".join(out)


@pytest.mark.parametrize("stem", NAMES, ids=[ascii(n)[2:-1] for n in NAMES])
def test_the_report_shows_the_name_and_keeps_its_shape(tmp_path, stand_ins, log_bytes, stem):
    plain_path, plain_md, plain_html = _report(tmp_path / "plain", PLAIN, log_bytes)
    path, md, report_html = _report(tmp_path / "named", stem, log_bytes)
    # report.md: no line more (a newline in the name), no raw byte that is not UTF-8
    assert len(md.splitlines()) == len(plain_md.splitlines())
    for name, render in _renderers().items():
        expected, got = _tree(render(plain_md)), _tree(render(md))
        assert got.tags == expected.tags, name  # no <script>, no <em>, no cell more or less
        assert got.rows == expected.rows, name
        # the head, Figure 1's "Input:" and table cell, Figure 5's "Input:" and words
        assert _shown_in(expected.text, plain_path) == _shown_in(got.text, path) >= 4, name
        swapped = expected.text.replace(_ls_b(plain_path), _ls_b(path))
        assert got.text == swapped, name
    # report.html as the package writes it: the structure and text of Python-Markdown's
    page, plain_page = _tree(report_html), _tree(plain_html)
    assert page.tags == plain_page.tags and page.rows == plain_page.rows
    assert page.text == plain_page.text.replace(_ls_b(plain_path), _ls_b(path))
    if b"<script>" in stem:
        assert "<script>" not in report_html and html.escape("<script>") in report_html


def test_markdown_path_in_a_table_cell():
    r"""Each ``|`` is ``\|`` between code spans: one cell in either renderer, the name's text."""
    for stem in NAMES:
        cell = _common.markdown_path(os.fsdecode(stem), in_table=True)
        table = f"| a | b |\n|---|---|\n| x | {cell} |\n"
        for name, render in _renderers().items():
            tree = _tree(render(table))
            assert tree.rows == [2, 2], (name, stem)
            assert re.sub(r"\s+", " ", tree.text).strip().endswith(_ls_b(stem)), (name, stem)


def test_a_shipped_log_is_still_told_from_its_source():
    """The source's path (not its Markdown) says which shipped log it is."""
    shipped = _common._data_dir() / "kaos_closedloop.npz"
    assert _common.shipped_log(_common.log_source(shipped)) == "simulated"
    assert _common.shipped_log(_common.log_source(Path("/elsewhere/kaos_closedloop.npz"))) is None
    assert _common.shipped_log(_common.SYNTHETIC_SOURCE) == "spectral"
