"""``paper_figures._common.markdown_path`` of a name that starts or ends with a backtick.

Mutation round 33 (docs/MUTATION.md): fix50-b's names hold backticks only inside
(``a`b``c``), so a code span padded only when the name starts *and* ends with one passed
(CommonMark 0.31, sec. 6.1: a code span whose content starts or ends with a backtick needs a
space inside its fences, which the renderer strips). References: markdown-it-py's
CommonMark renderer and Python-Markdown (what report.html is made with): the rendered
``<code>`` text, HTML-unescaped, is the name.
"""

from __future__ import annotations

import html
import re

import pytest

from paper_figures import _common


def _code_texts(rendered: str) -> list[str]:
    return [html.unescape(t) for t in re.findall(r"<code>(.*?)</code>", rendered, re.S)]


@pytest.mark.parametrize("name", ["`lead.npz", "trail.npz`", "`both`", "in`side.npz"])
def test_a_backtick_at_either_end_is_shown(name):
    import markdown
    from markdown_it import MarkdownIt

    md = _common.markdown_path(name)
    for render in (MarkdownIt("commonmark").render, markdown.markdown):
        assert _code_texts(render(f"Input: {md}.")) == [name], (render, md)
