"""``modalinfo info`` shows the quality pass's progress on a large log (issue 27, left28-quality).

Adversarial round 27 PART b, S01: ``info`` of a 10^4 x 2000-mode log showed nothing for
97 s. The quality pass now reports its stages to a ``progress`` callable, and the
command lines drive a tqdm bar from it on a terminal for a log of at least
``QUALITY_PROGRESS_VALUES`` values, naming the memory the pass will take when above
1 GiB; piped output (a non-terminal stderr) stays clean. References from outside the
code: the number of stages the docstring states (5) counted by the test's own callable,
and stderr as a terminal would show it (``isatty`` patched, as
tests/cli/test_cli_user_trips.py does); the size threshold is lowered to the test log's
size so the test stays small.
"""

from __future__ import annotations

import sys

import numpy as np

import modalinfo.cli.shared as shared
import modalinfo.telemetry.quality as quality
from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog, assess_quality


def _log(tmp_path):
    x = np.random.default_rng(3).standard_normal((600, 6))
    path = tmp_path / "big.npz"
    save(ModalLog(x, rate=1000.0, modes=list(range(2, 8)), units="nm"), path)
    return str(path), x


def test_assess_quality_reports_its_five_stages(tmp_path):
    calls = []
    x = _log(tmp_path)[1]
    report = assess_quality(x, progress=calls.append)
    assert calls == [1] * 5
    assert report.describe() == assess_quality(x).describe()  # the hook changes nothing


def test_info_bar_on_a_terminal_only_with_the_memory(tmp_path, capsys, monkeypatch):
    path, _ = _log(tmp_path)
    monkeypatch.setattr(shared, "QUALITY_PROGRESS_VALUES", 600 * 6)
    monkeypatch.setattr(quality, "quality_memory", lambda n, m: 3 * 2**30)
    assert main(["info", path]) == 0  # piped (captured): no bar
    assert "quality pass" not in capsys.readouterr().err
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    assert main(["info", path]) == 0
    assert "quality pass (about 3.0 GiB)" in capsys.readouterr().err
    assert main(["info", path, "--quiet"]) == 0
    assert "quality pass" not in capsys.readouterr().err
    monkeypatch.setattr(shared, "QUALITY_PROGRESS_VALUES", 600 * 6 + 1)  # a smaller log
    assert main(["info", path]) == 0
    assert "quality pass" not in capsys.readouterr().err
