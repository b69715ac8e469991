r"""A user's name or mode label in a plot's title or axis label is drawn as shown, never as math.

Stop 56 left (fix49-c): ``modalinfo fitting-error LOG --plot`` titled the figure with
``args.log.name`` raw, so ``$x$.npz`` was typeset as mathtext (an italic x), ``a$^$b.npz``
stopped the drawing with mathtext's ``ValueError`` and a newline split the title; the
same held for a log's own mode labels (``convention="labels"``) in
``ForecastEvaluation.plot_series``'s y label (``modalinfo forecast --out``) and Figure
5's titles and y labels (``paper_figures --log``).

Reference, outside the package: matplotlib's Agg rendering of the expected text drawn
with ``parse_math=False`` (no mathtext whatever it holds): the figure's text, drawn the
same way with matplotlib's default parsing, must give the same pixels. The expected text
is the name in ``ls -b``'s form (``\n`` for a newline), written out here.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from matplotlib.figure import Figure

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog

#: (name, as ls -b shows it): two "$" (mathtext before), one "$", mathtext that does not
#: parse, a newline
NAMES = [("$x$", "$x$"), ("a$b", "a$b"), ("a$^$b", "a$^$b"), ("a\nb", "a\\nb"),
         ("$\\alpha$", "$\\\\alpha$")]
IDS = ["math", "one-dollar", "bad-math", "newline", "backslash-math"]
#: a mode label is printable (ModalLog refuses a newline in one)
LABELS = pytest.mark.parametrize(("name", "shown"), [n for n in NAMES if n[0] != "a\nb"],
                                 ids=[i for i in IDS if i != "newline"])


def _pixels(text: str, **kwargs) -> np.ndarray:
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = Figure(figsize=(6, 1), dpi=72)
    canvas = FigureCanvasAgg(fig)
    fig.text(0.01, 0.5, text, fontsize=10, **kwargs)
    canvas.draw()
    return np.asarray(canvas.buffer_rgba()).copy()


def _drawn_as(text: str, expected: str) -> bool:
    """Whether ``text``, drawn as matplotlib draws a title, looks as ``expected`` typed."""
    return np.array_equal(_pixels(text), _pixels(expected, parse_math=False))


def test_the_reference_tells_math_from_text():
    """The reference can fail: raw ``$x$`` is drawn as math, not as the four characters."""
    assert not _drawn_as("$x$", "$x$")
    assert _drawn_as("ab", "ab")


@pytest.mark.parametrize(("name", "shown"), NAMES, ids=IDS)
def test_fitting_error_plot_title(tmp_path, monkeypatch, name, shown, capsys):
    from modalinfo.ordering import compare

    rng = np.random.default_rng(0)
    log = ModalLog(rng.standard_normal((200, 9)), modes=list(range(2, 11)), units="rad",
                   rate=1000.0, wavelength=5e-7)
    path = save(log, tmp_path / f"{name}.npz")
    saved = []
    real = compare.save_figure
    monkeypatch.setattr(compare, "save_figure",
                        lambda fig, *a, **k: saved.append(fig) or real(fig, *a, **k))
    assert main(["fitting-error", str(path), "--orderings", "zernike:standard",
                 "--pupil-pixels", "32", "--plot", str(tmp_path / "f.png")]) == 0, (
        capsys.readouterr().err)
    title = saved[0].axes[0].get_title()
    assert _drawn_as(title, f"{shown}.npz: frame average"), ascii(title)


@LABELS
def test_forecast_series_label(name, shown):
    from modalinfo.forecast import LinearPredictor, evaluate

    rng = np.random.default_rng(0)
    log = ModalLog(np.cumsum(rng.standard_normal((200, 2)), axis=0), modes=[name, "b"],
                   convention="labels", units="rad", rate=1000.0, wavelength=5e-7)
    ev = evaluate({"lin": LinearPredictor()}, log, train=0.5, horizons=[1, 2])
    fig = Figure()
    ax = ev.plot_series(0, ax=fig.add_subplot())
    assert _drawn_as(ax.get_ylabel(), f"{shown} [rad]"), ascii(ax.get_ylabel())


@LABELS
def test_figure_5_titles_and_labels(tmp_path, name, shown):
    from paper_figures import fig5_forecast as fig5

    from ..paper_figures.conftest import saved_figures
    from ..paper_figures.test_mutation_gaps_fig5_forecast import _figure

    with saved_figures() as figures:
        fig5.plot(dataclasses.replace(_figure(), label=name), tmp_path)
    axes = figures[fig5.output_names("")[0]].axes
    assert _drawn_as(axes[0].get_title(), f"(a) linear predictor, {shown}")
    for ax in axes[:3]:
        assert _drawn_as(ax.get_ylabel(), f"{shown} [rad]"), ascii(ax.get_ylabel())
