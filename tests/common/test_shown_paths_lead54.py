r"""The last raw paths in one-line messages (stop 54, review30's "found, not fixed" 1 and 2).

``check_out_dir`` named the missing parent raw next to the quoted folder (the same path two
ways: ``'d\\e/sub/x': 'd\e/sub' does not exist``), and ``python -m paper_figures``' own
``--log`` refusals wrote the user's path raw. Reference: the ``ls -b`` form written by hand
(``d\\e`` for the name ``d\e``) and ``codecs.escape_decode`` of every quoted name giving the
name's bytes back; the raw form absent.
"""

from __future__ import annotations

import codecs
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from modalinfo.common.folders import OutputError, check_out_dir

NAME = "d\\e"


def _decoded(text: str) -> list[bytes]:
    return [codecs.escape_decode(m.encode("utf-8"))[0] for m in re.findall(r"'([^']*)'", text)]


def test_missing_parent_is_named_in_the_shown_form(tmp_path: Path) -> None:
    out = tmp_path / NAME / "sub" / "x"
    with pytest.raises(OutputError) as info:
        check_out_dir(out, parents=False)
    text = str(info.value)
    assert f"{NAME}/sub'" not in text, text
    assert os.fsencode(str(tmp_path / NAME / "sub")) in _decoded(text), text


def test_paper_figures_log_refusal_names_the_shown_path(tmp_path: Path) -> None:
    missing = tmp_path / NAME / "log.npz"
    run = subprocess.run([sys.executable, "-m", "paper_figures", "--only", "1", "--log",
                          str(missing), "--out", str(tmp_path / "out")],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 2, run.stderr
    assert f"{NAME}/log.npz'" not in run.stderr, run.stderr
    assert os.fsencode(str(missing)) in _decoded(run.stderr), run.stderr
