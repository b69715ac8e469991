"""``report.html`` (``paper_figures/_html.py``) parsed back, image by image.

Written for mutation testing (issue 26 item 3, docs/MUTATION.md). References, all
outside the module:

- the HTML parsed by :mod:`html.parser` (the document's title, language, character set,
  style, headings, table cells and every ``<img src>``), never searched as text;
- the module docstring's rule: an image that names a PNG file *of the output folder*
  becomes a ``data:image/png;base64`` URI whose bytes, decoded by :mod:`base64`, are the
  file's (round trip); any other image (a subfolder, a parent, another format, a missing
  file, a folder) is left as written;
- the CSS read back: every rule of the style sheet selects HTML elements (a mangled
  selector styles nothing).
~1 s.
"""

from __future__ import annotations

import base64
import re
from html.parser import HTMLParser

import pytest

from paper_figures._html import report_html

PNG = b"\x89PNG\r\n\x1a\n" + bytes(range(256)) * 3


class Page(HTMLParser):
    """What a browser would read: tags with attributes, text per tag."""

    def __init__(self, text):
        super().__init__(convert_charrefs=True)
        self.tags, self.text, self.decl, self._open = [], {}, [], []
        self.feed(text)
        self.close()

    def handle_decl(self, decl):
        self.decl.append(decl)

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))
        self._open.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))

    def handle_endtag(self, tag):
        if self._open and self._open[-1] == tag:
            self._open.pop()

    def handle_data(self, data):
        if self._open:
            self.text[self._open[-1]] = self.text.get(self._open[-1], "") + data

    def images(self):
        return [a for t, a in self.tags if t == "img"]

    def names(self):
        return [t for t, _ in self.tags]


def decoded(src):
    head, _, data = src.partition(",")
    assert head == "data:image/png;base64"
    return base64.b64decode(data, validate=True)


def test_the_document(tmp_path):
    page = Page(report_html("# Report\n\nSome *text*.\n", tmp_path, title="Tom & Jerry <3>"))
    assert page.decl == ["DOCTYPE html"]
    assert page.names()[:5] == ["html", "head", "meta", "title", "style"]
    assert page.tags[0][1] == {"lang": "en"}
    assert page.tags[2][1] == {"charset": "utf-8"}
    assert page.text["title"] == "Tom & Jerry <3>"
    assert page.text["h1"] == "Report" and page.text["em"] == "text"
    assert "body" in page.names()
    assert Page(report_html("x", tmp_path)).text["title"] == "modalinfo report"


def test_the_style_sheet_styles_html_elements(tmp_path):
    page = Page(report_html("x", tmp_path))
    rules = re.findall(r"([^{}]+)\{([^{}]*)\}", page.text["style"])
    selectors = {s.strip() for sel, _ in rules for s in sel.split(",")}
    assert selectors == {"body", "table", "th", "td", "img", "code"}
    assert all(":" in body for _, body in rules)
    assert "".join(f"{a}{{{b}}}" for a, b in rules) == page.text["style"]


def test_a_markdown_table_is_an_html_table(tmp_path):
    page = Page(report_html("| a | b |\n|---|---|\n| 1 | 2 |\n", tmp_path))
    assert [t for t in page.names() if t in ("table", "th", "td")] == \
        ["table", "th", "th", "td", "td"]


def test_images_of_the_folder_are_embedded(tmp_path):
    (tmp_path / "fig.png").write_bytes(PNG)
    (tmp_path / "A&B.PNG").write_bytes(PNG[::-1])      # an escaped name, upper-case suffix
    page = Page(report_html("![Figure 1](fig.png)\n\n![two](A&B.PNG)\n", tmp_path))
    first, second = page.images()
    assert first["alt"] == "Figure 1" and decoded(first["src"]) == PNG
    assert second["alt"] == "two" and decoded(second["src"]) == PNG[::-1]


@pytest.mark.parametrize("src", ["sub/fig.png", "sub\\fig.png", "../fig.png", "fig.jpg",
                                 "missing.png", "folder.png", "fig.png.txt"])
def test_other_images_are_left_as_written(tmp_path, src):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "fig.png").write_bytes(PNG)
    (tmp_path / "folder.png").mkdir()
    (tmp_path / "fig.jpg").write_bytes(PNG)
    (tmp_path / "fig.png.txt").write_bytes(PNG)
    (tmp_path / "sub\\fig.png").write_bytes(PNG)   # one file on POSIX, a subfolder's on Windows
    (tmp_path.parent / "fig.png").write_bytes(PNG)
    page = Page(report_html(f"![x]({src})\n", tmp_path))
    assert [i["src"] for i in page.images()] == [src]
