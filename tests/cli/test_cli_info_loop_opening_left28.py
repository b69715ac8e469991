"""``modalinfo info`` of a log whose loop opened mid-way names the spread step (N01).

Issue 27, left28-nonstat (adversarial round 28 PART b, N01: the quality line named "the
mean steps or drifts in 2 mode(s)" but not the x10 spread step every mode has).
Reference: the planted truth of round 28 PART b's generator (AR(1) 0.9, rms 0.05, for
4000 frames, then AR(1) 0.999, rms 0.5: x10 in every mode at frame 4000).
"""

from __future__ import annotations

import re

import numpy as np

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


def _ar1(rng, n, phi, sig, m=6):
    e = rng.normal(0, sig * np.sqrt(1 - phi ** 2), (n, m))
    x = np.zeros((n, m))
    x[0] = rng.normal(0, sig, m)
    for i in range(1, n):
        x[i] = phi * x[i - 1] + e[i]
    return x


def test_info_names_the_spread_step_of_a_loop_opening(tmp_path, capsys):
    rng = np.random.default_rng(5)
    x = np.vstack([_ar1(rng, 4000, 0.9, 0.05), _ar1(rng, 4000, 0.999, 0.5)])
    path = save(ModalLog(x, rate=2000.0, modes=list(range(2, 8)), units="rad"),
                tmp_path / "loopopen.npz")
    assert main(["info", str(path)]) == 0
    out = capsys.readouterr().out
    line = next(row for row in out.splitlines() if row.startswith("quality"))
    found = re.search(r"the spread steps or drifts in (\d+) mode\(s\) \(([^;]*)", line)
    assert found and int(found.group(1)) == 6
    frames = [int(f) for f in re.findall(r"at frame (\d+) \(x", found.group(2))]
    ratios = [float(r) for r in re.findall(r"\(x([\d.]+)\)", found.group(2))]
    assert frames and all(abs(f - 4000) < 200 for f in frames)
    assert ratios and all(r > 3.0 for r in ratios)  # the opening grows every mode
