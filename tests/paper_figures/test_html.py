"""report.html: the Markdown report with its figures inline.

References: the PNG bytes decoded from the data URI equal the file's (round trip), the
table is an HTML table (Python-Markdown's ``tables`` extension), and an image that is not
a file of the output directory is left as it is.
"""

import base64
import re

from paper_figures._html import report_html


def test_report_html_embeds_the_figures(tmp_path):
    png = b"\x89PNG\r\n\x1a\n" + bytes(range(256))
    (tmp_path / "fig.png").write_bytes(png)
    text = ("# Title\n\n| a | b |\n|---|---|\n| 1 | 2 |\n\n![Figure](fig.png)\n\n"
            "![elsewhere](../other.png)\n")
    out = report_html(text, tmp_path)
    assert "<table>" in out and "<td>1</td>" in out and "<h1>Title</h1>" in out
    data = re.search(r'src="data:image/png;base64,([^"]+)"', out).group(1)
    assert base64.b64decode(data) == png
    assert 'src="../other.png"' in out
    assert out.startswith("<!DOCTYPE html>")
