"""Figures and reports given back as a log are named (round 54 PART b, O08-O22, O35-O40).

Reference: the files themselves, written by matplotlib's own ``savefig`` in each format
``fitting-error --plot`` accepts (JPEG, GIF, TIFF, WebP, AVIF, PS, EPS, SVG, SVGZ) and an
HTML page as ``paper_figures`` writes it; their kinds are the formats' published magic
numbers (JFIF/JPEG ``FF D8 FF``, ``GIF89a``, TIFF ``II*\\0``, RIFF ``WEBP``, ISO-BMFF
``ftypavif``, ``%!PS``) or first tags (``<svg``, ``<!DOCTYPE html>``). Before the fix they
were "corrupt CSV file ... could not convert string '<!DOCTYPE'" or "a CSV must be UTF-8:
re-save it as UTF-8", and an SVGZ was told to be gunzipped, which gunzip refuses for that
suffix. Guards: a log and a gzip-compressed CSV log are still read / named as before.
"""

from __future__ import annotations

import gzip
import re

import numpy as np
import pytest

from modalinfo.io.files import LogFormatError
from modalinfo.io.formats import detect_format


def _figure(path):
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure

    fig = Figure(figsize=(2, 2))
    fig.subplots().plot([0, 1], [1, 0])
    fig.savefig(path)


@pytest.mark.parametrize("suffix, what", [
    (".jpg", "a JPEG image"), (".gif", "a GIF image"), (".tif", "a TIFF image"),
    (".webp", "a WebP image"), (".eps", "a PostScript (PS / EPS) figure"),
    (".ps", "a PostScript (PS / EPS) figure"), (".svg", "an SVG image"),
    (".svgz", "an SVG image compressed with gzip")])
def test_matplotlib_figure_is_named(tmp_path, suffix, what):
    path = tmp_path / f"fe{suffix}"
    _figure(path)
    with pytest.raises(LogFormatError, match=re.escape(f"is {what}, not a log")):
        detect_format(path)


def test_avif_is_named(tmp_path):
    pil = pytest.importorskip("PIL.Image")
    if ".avif" not in pil.registered_extensions():
        pytest.skip("this Pillow writes no AVIF")
    path = tmp_path / "fe.avif"
    _figure(path)
    with pytest.raises(LogFormatError, match="is an AVIF image, not a log"):
        detect_format(path)


def test_html_report_is_named(tmp_path):
    path = tmp_path / "report.html"
    path.write_text("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"></head>\n<body>"
                    + "x" * 200_000 + "</body></html>\n", encoding="utf-8")
    with pytest.raises(LogFormatError, match="is an HTML document, not a log"):
        detect_format(path)


def test_logs_still_read(tmp_path):
    # a CSV log and a gzip-compressed CSV log: read / told to decompress, as before
    path = tmp_path / "log.csv"
    np.savetxt(path, np.random.default_rng(54).normal(size=(20, 3)), delimiter=",",
               header="Z2,Z3,Z4", comments="")
    assert detect_format(path) == "csv"
    gz = tmp_path / "log.csv.gz"
    gz.write_bytes(gzip.compress(path.read_bytes()))
    with pytest.raises(LogFormatError, match=r"gzip-compressed; decompress it first"):
        detect_format(gz)
