"""Round 19 PART b: a user's matplotlib configuration that this machine cannot draw with.

References from outside the code: matplotlib itself (``font_manager.findfont(...,
fallback_to_default=False)`` raises for a family it cannot find; ``text.usetex`` needs
``latex`` on ``PATH``, here replaced by a ``shutil.which`` that finds nothing), the PNG
signature (``\\x89PNG\\r\\n\\x1a\\n``, RFC 2083) and ``matplotlib.rcParams`` read back after
the call. Before the fix ``text.usetex: True`` without LaTeX raised matplotlib's
``RuntimeError`` after the work (``modalinfo forecast --out`` lost its results,
``fitting-error --plot`` exited 0 without its figure, ``paper_figures`` exited 1), and a
missing ``font.family`` logged one ``findfont`` line per text drawn (558 for one
``forecast --out``).
"""

import logging

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib import font_manager  # noqa: E402

from modalinfo.batch.report import plot_archive  # noqa: E402
from modalinfo.common import plotting  # noqa: E402
from modalinfo.forecast import LinearPredictor, evaluate  # noqa: E402

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(autouse=True)
def _fresh(monkeypatch):
    monkeypatch.setattr(plotting, "_WARNED", set())


def _evaluation():
    rng = np.random.default_rng(0)
    x = np.cumsum(rng.standard_normal((200, 2)), axis=0)
    return evaluate({"lin": LinearPredictor()}, x, train=0.5, horizons=[1, 2])


def test_usetex_without_latex_draws_and_says_so_once(tmp_path, monkeypatch):
    monkeypatch.setattr(plotting.shutil, "which", lambda name: None)  # no LaTeX here
    ev = _evaluation()
    with matplotlib.rc_context({"text.usetex": True}):
        with pytest.warns(UserWarning, match="text.usetex") as caught:
            paths = ev.save_plots(tmp_path)
            (tmp_path / "again").mkdir()
            ev.save_plots(tmp_path / "again")  # a second drawing: no second warning
        assert matplotlib.rcParams["text.usetex"] is True  # the user's setting is back
    assert [str(w.message).count("usetex") for w in caught] == [1]
    for path in paths:
        assert path.read_bytes()[:8] == PNG


def test_usetex_kept_where_latex_exists(monkeypatch):
    monkeypatch.setattr(plotting.shutil, "which", lambda name: f"/usr/bin/{name}")
    with matplotlib.rc_context({"text.usetex": True}):
        assert plotting.rc_overrides() == {}


def test_missing_font_family_warns_once_not_per_text(tmp_path, caplog):
    family = "NoSuchFontFamilyRound19"
    with pytest.raises(ValueError):  # matplotlib's own word: not installed
        font_manager.findfont(font_manager.FontProperties(family=[family]),
                              fallback_to_default=False)
    rows = [{"analysis": "summary", "status": "ok", "path": f"{k}.npz", "rate": 1000.0 * k,
             "rms_total": 0.1 * k} for k in (1, 2, 3)]
    with matplotlib.rc_context({"font.family": [family, "sans-serif"]}):
        with caplog.at_level(logging.WARNING, logger="matplotlib.font_manager"):
            with pytest.warns(UserWarning, match=family):
                ev = _evaluation()
                ev.save_plots(tmp_path)
                plot_archive(rows, tmp_path / "plots")
        assert matplotlib.rcParams["font.family"] == [family, "sans-serif"]
    assert [r for r in caplog.records if "findfont" in r.getMessage()] == []
    for path in tmp_path.glob("*.png"):
        assert path.read_bytes()[:8] == PNG
