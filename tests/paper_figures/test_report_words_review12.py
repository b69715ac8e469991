"""A user's log named like a shipped one is still the user's (review12, round 12).

Reference (outside the code): where the file is. ``data/README.md`` describes the two
logs shipped in ``data/``; a file elsewhere that happens to carry the same name (a
user's own ``kaos_closedloop.npz``, here a copy of the shipped bytes, so only its folder
tells) is the user's log: Figure 5's report names it and Figure 1 does not call it our
closed-loop residual.
"""

from __future__ import annotations

import dataclasses
import shutil
from pathlib import Path

import pytest

from paper_figures import fig5_forecast as fig5
from paper_figures._common import shipped_log

from .test_mutation_gaps_fig5_forecast import _figure

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.mark.parametrize("name", ["kaos_like_closed_loop.npz", "kaos_closedloop.npz"])
def test_a_user_file_with_a_shipped_name_is_the_users(tmp_path, name):
    copy = tmp_path / name
    shutil.copyfile(DATA / name, copy)
    source = f"`{copy}`"
    assert shipped_log(source) is None
    text = fig5.report(dataclasses.replace(_figure(), source=source))
    assert f"- This is your log {source}; the paper shows" in text
    assert shipped_log(f"`{DATA / name}`") is not None  # the shipped file itself
