"""Figure 5's report says what its log is: a shipped log's words, a user's log by its name.

Issue 27, leftovers 12-cli item 3. Reference, outside the code: ``data/README.md``, which
says what the two shipped logs are (the spectral ``kaos_like_closed_loop.npz``: a
closed-loop WFS-measured residual with WFS noise, a synthetic KAOS-like log; the simulated
``kaos_closedloop.npz``: the WFS-reconstructed residual of ``closedloop``'s ``kaos``
preset), and the file name the user gave. The report is built from the hand-made
``Figure5`` of the mutation-gap tests (``_figure``), its source replaced.
"""

from __future__ import annotations

import dataclasses
import os
import shutil
from pathlib import Path

import pytest

from paper_figures import fig5_forecast as fig5

from .test_mutation_gaps_fig5_forecast import _figure

DATA = Path(__file__).resolve().parents[2] / "data"
#: what the report's Input line says of the synthetic log (no --log, a stand-alone run)
SYNTHETIC_SOURCE = "synthetic `kaos_like(seed=0)` (closed loop, not real data)"
USER_WORDS = ("closed-loop residual plus WFS noise", "synthetic KAOS-like", "simulated by")


def _report(source: str) -> str:
    return fig5.report(dataclasses.replace(_figure(), source=source))


def test_a_user_log_is_named_not_described_as_ours(tmp_path):
    # a copy of a shipped log elsewhere is the user's file: named, not described
    copy = tmp_path / "pol.npz"
    shutil.copyfile(DATA / "kaos_like_closed_loop.npz", copy)
    for source in ("`pol.fits`", f"`{copy}`"):
        text = _report(source)
        assert f"your log {source} has rough, anti-correlated increments." in text
        assert f"- This is your log {source}; the paper shows" in text
        assert not any(words in text for words in USER_WORDS)


@pytest.mark.parametrize("source", [f"`{DATA / 'kaos_like_closed_loop.npz'}`",
                                    SYNTHETIC_SOURCE])
def test_the_spectral_log_keeps_its_words(source):
    text = _report(source)
    assert "the closed-loop residual plus WFS noise has rough" in text
    assert "This is a synthetic KAOS-like log (an integrator loop" in text
    assert "your log" not in text


def test_the_simulated_log_is_not_called_synthetic(tmp_path, monkeypatch):
    # given by a relative path through a link: still the shipped file
    (tmp_path / "d").symlink_to(DATA)
    monkeypatch.chdir(tmp_path)
    source = f"`{os.path.join('d', 'kaos_closedloop.npz')}`"
    text = _report(source)
    assert "the closed-loop residual plus WFS noise has rough" in text
    assert "This is a log simulated by `closedloop` (its `kaos` preset" in text
    assert "synthetic KAOS-like" not in text and "your log" not in text
