"""Round 30 PART b (issue 27): ``scale_steps`` names the frames of a step, not any block.

docs/ADVERSARIAL.md, "Round 30 PART b, issue 27", Q03 / Q04: the per-mode scale rule
named the block farthest from the median block scale; for a change that lasts (Z2 / Z3
innovations x3 from frame 10,000 of 20,000) every block is about as far, and the report
read "Z2 x3.1 in frames 2504-5004". The frames are now the run of blocks on the far
block's side, i.e. one side of the step.

Reference: the planted change frame (10,000) and episode (frames 9,500-10,500) of AR(1)
logs made with ``scipy.signal.lfilter``; the run of hand-made block scales.
"""

from __future__ import annotations

import numpy as np
from scipy.signal import lfilter

from modalinfo._stats import block_run
from modalinfo.io import ModalLog
from modalinfo.telemetry.quality import assess_quality


def _log(scale, seed):
    e = np.random.default_rng(seed).normal(size=scale.shape) * scale
    return ModalLog(0.01 * lfilter([1.0], [1.0, -0.95], e, axis=0), rate=2000.0)


def test_block_run_by_hand():
    step = np.log([1, 1.1, 0.9, 1, 3, 3.2, 2.9, 3])
    assert block_run(step, 5) == (4, 7)
    assert block_run(step, 1) == (0, 3)
    episode = np.log([1, 1, 1, 2.5, 2.4, 1, 1, 1])
    assert block_run(episode, 3) == (3, 4)
    assert block_run(np.array([0.0, -np.inf, 1.0, 1.0]), 2) == (2, 3)


def test_a_lasting_change_names_one_side_of_the_step():
    scale = np.ones((20000, 6))
    scale[10000:, :2] = 3.0
    for seed in range(3):
        report = assess_quality(_log(scale, 100 + seed))
        named = {label: (start, stop) for label, start, stop, _, _ in report.scale_steps}
        assert set(named) == {"Z2", "Z3"}
        for start, stop in named.values():
            edge = stop if start < 10000 else start
            assert abs(edge - 10000) <= 20000 // 32  # one of the smallest blocks
            assert start < 1000 or stop > 19000  # the half reaches the log's end


def test_an_episode_is_still_its_blocks():
    scale = np.ones((20000, 6))
    scale[9500:10500] = 2.5
    report = assess_quality(_log(scale, 7))
    assert len(report.scale_steps) == 6
    for _, start, stop, _, _ in report.scale_steps:
        assert start < 10500 and stop > 9500  # overlaps the episode
        assert stop - start <= 2 * 1000 + 2 * 20000 // 32
