r"""Stop 57, fix51-c item 5: ``plot_text`` under matplotlib's ``text.usetex``.

``modalinfo.common.plotting.plot_text`` escaped a user's text (a file name, a mode label)
for mathtext only (``$`` -> ``\$``); with ``rcParams["text.usetex"] = True`` and a LaTeX
installed (``drawable_rc`` keeps usetex then), TeX reads the whole text, and ``_``,
``%``, ``&``, ``#``, ``^``, ``~``, ``{``, ``}`` and ``\`` are TeX's, not the user's.

References, outside the package: the special characters of LaTeX's text mode and the
commands that typeset each (Lamport, "LaTeX: A Document Preparation System", 2nd ed.,
Sect. 2.2.1 and C.3.4: ``\# \$ \% \& \_ \{ \}``, ``\textbackslash``,
``\textasciicircum``, ``\textasciitilde``; ``\textless``, ``\textgreater``, ``\textbar``
for the three OT1 fonts set as other glyphs), written out here; and, where ``latex`` and
``dvipng`` are installed, matplotlib's own usetex rendering of the title (it raises on a
TeX error). Skipped without them (this machine has none).
"""

from __future__ import annotations

import shutil

import matplotlib
import pytest

from modalinfo.common.plotting import plot_text

EXPECTED = {"a_b": r"a\_b", "50%": r"50\%", "R&D": r"R\&D", "#3": r"\#3", "$x$": r"\$x\$",
            "a^2": r"a\textasciicircum{}2", "~me": r"\textasciitilde{}me",
            "{k}": r"\{k\}", "a\\b": r"a\textbackslash{}\textbackslash{}b",
            "<b>|": r"\textless{}b\textgreater{}\textbar{}", "Z2 (tip)": "Z2 (tip)"}


@pytest.mark.parametrize("text", sorted(EXPECTED))
def test_usetex_escapes_every_special_character(text):
    # "a\\b": shown_name writes a backslash as "\\" (ls -b), each typeset as a backslash
    with matplotlib.rc_context({"text.usetex": True}):
        assert plot_text(text) == EXPECTED[text]
    assert plot_text(text, usetex=True) == EXPECTED[text]


@pytest.mark.parametrize("text", sorted(EXPECTED))
def test_without_usetex_only_the_dollar_is_escaped(text):
    # mathtext's rule, unchanged (tests/common/test_plot_text_fix50b.py draws it)
    shown = text.replace("\\", "\\\\")
    with matplotlib.rc_context({"text.usetex": False}):
        assert plot_text(text) == shown.replace("$", "\\$")


@pytest.mark.skipif(not (shutil.which("latex") and shutil.which("dvipng")),
                    reason="no LaTeX installation (latex, dvipng) on PATH")
def test_usetex_draws_every_special_character(tmp_path):
    from matplotlib.figure import Figure

    with matplotlib.rc_context({"text.usetex": True}):
        fig = Figure()
        ax = fig.subplots()
        ax.set_title(plot_text("".join(EXPECTED)))
        ax.set_ylabel(f"{plot_text('mode_1 50% #2')} [rad]")
        fig.savefig(tmp_path / "t.png")  # a TeX error raises here
