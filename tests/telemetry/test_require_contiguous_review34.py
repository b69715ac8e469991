"""``require_contiguous``'s remedy: the default and a caller's own (review34, round 34).

Round 51 PART b (C101 / C105) gave ``telemetry.sampling.require_contiguous`` a ``remedy``
for ``modalinfo batch``, which has no ``--split-gaps``; every other caller keeps the
default, which names the command-line option the commands accept. Reference: the option
as the parsers define it (``modalinfo forecast LOG --split-gaps`` parses), and the
gap is the test's own (frames 100..109 removed from a 1 kHz log's timestamps; the longest
contiguous segment is frames 100..299 of the 300 kept).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.cli import build_parser
from modalinfo.telemetry import ModalLog
from modalinfo.telemetry.sampling import require_contiguous


def _gapped() -> ModalLog:
    frames = np.r_[0:100, 110:310]
    x = np.random.default_rng(34).normal(size=(frames.size, 2))
    return ModalLog(x, timestamps=frames / 1000.0, modes=[2, 3], units="rad")


def test_the_default_remedy_names_the_command_line_option():
    with pytest.raises(ValueError) as info:
        require_contiguous(_gapped(), "forecast evaluation")
    message = str(info.value)
    assert message.endswith("(command line: --split-gaps)")
    assert "frames 100..299" in message
    # the option the default names is the commands' own
    assert build_parser().parse_args(["forecast", "x.npz", "--split-gaps"]).split_gaps


def test_a_callers_remedy_replaces_the_default():
    with pytest.raises(ValueError) as info:
        require_contiguous(_gapped(), "forecast evaluation", remedy="batch has none")
    message = str(info.value)
    assert message.endswith("(batch has none)")
    assert "command line" not in message
