"""``report.html``: the Markdown report as one self-contained HTML file (figures inline).

The Markdown is converted by Python-Markdown (with its ``tables`` extension) and every
``<img src="NAME.png">`` that names a file in the output directory is replaced by a
``data:image/png;base64`` URI, so a colleague can open the one file anywhere.
"""

from __future__ import annotations

import base64
import html
import re
from pathlib import Path

__all__ = ["report_html"]

_STYLE = """body{font-family:sans-serif;max-width:60em;margin:2em auto;line-height:1.45;
padding:0 1em}table{border-collapse:collapse;margin:1em 0}th,td{border:1px solid #bbb;
padding:.25em .5em;text-align:left}th{background:#eee}img{max-width:100%}
code{background:#f4f4f4}"""


def report_html(markdown_text: str, image_dir: Path, *, title: str = "modalinfo report") -> str:
    """Return the report as HTML with the PNG figures of ``image_dir`` embedded."""
    import markdown

    body = markdown.markdown(markdown_text, extensions=["tables"])

    def embed(match: re.Match) -> str:
        src = html.unescape(match.group(2))
        path = Path(image_dir) / src
        if "/" in src or "\\" in src or not src.lower().endswith(".png") or not path.is_file():
            return match.group(0)
        data = base64.b64encode(path.read_bytes()).decode("ascii")
        return f'{match.group(1)}"data:image/png;base64,{data}"'

    body = re.sub(r'(<img[^>]*?src=)"([^"]+)"', embed, body)
    return (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{html.escape(title)}</title><style>{_STYLE}</style></head>\n"
            f"<body>\n{body}\n</body></html>\n")
