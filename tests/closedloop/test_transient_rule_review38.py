"""Which runs get the servo model's closure transient, and with which loop (mutation round 38).

``SimulationResult.transient_frames`` of a loop "closed, still converging" (or "closed,
SR too small to show it") under the integrator alone is the first command's frame plus
3 closed-loop time constants, at most mid-run; any other run keeps ``averaging_start``
(fix56-c). The run is fix56-c's (kaos at gain 0.02, 0.5 s, seed 1, "closed, still
converging"); its status is read from its residual, so the same run with another loop
in its config (another gain, delay or leak) or another predictor name keeps that status
while the rule reads the new config.

References (from outside the code): the time constant -1 / ln r, r the largest modulus
of the roots (``numpy.roots``) of the loop's characteristic polynomial written by hand
from the sampled model, z**(d+1) - (1 - leak) z**d + g for a delay of d frames and a
full-frame exposure (the command applied d frames after the frame that measured it
ends: W(z) = z**-(d+1)); the first command's frame floor(delay) + 1; mid-run T // 2.
A transient dataset that is not one integer is refused as a missing one (h5py).
Each test names the plant of docs/MUTATION.md's round 38 it fails with.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from closedloop import SimulationResult, presets, simulate


@pytest.fixture(scope="module")
def slow():
    base = presets.get("kaos")
    cfg = dataclasses.replace(base, loop=dataclasses.replace(base.loop, gain=0.02))
    run = simulate(cfg, 0.5, seed=1, progress=False)
    assert run.loop_status.startswith("closed, still converging")
    return run


def _with_loop(run, **loop):
    cfg = dataclasses.replace(run.config, loop=dataclasses.replace(run.config.loop, **loop))
    return dataclasses.replace(run, config=cfg)


def _servo_transient(gain: float, delay: int, leak: float) -> int:
    poly = np.zeros(delay + 2)
    poly[0], poly[1], poly[-1] = 1.0, -(1.0 - leak), gain  # z**(d+1) - (1-leak) z**d + g
    r = float(np.max(np.abs(np.roots(poly))))
    return delay + 1 + math.ceil(3 * -1.0 / math.log(r))


@pytest.mark.parametrize(("gain", "delay", "leak", "expected"),
                         [(0.2, 2, 0.0, 13), (0.02, 1, 0.05, 43)])
def test_the_transient_reads_the_runs_delay_and_leak(slow, gain, delay, leak, expected):
    """R38-RE6 (delay and exposure swapped: 10 for 13), R38-RE7 (leak dropped: 148 for 43)."""
    step = slow.config.loop.time_step
    run = _with_loop(slow, gain=gain, delay=delay * step, integration_time=step, leak=leak)
    assert (run.config.loop.delay_frames, run.config.loop.integration_frames) == (delay, 1.0)
    assert run.loop_status == slow.loop_status
    assert run.transient_frames == _servo_transient(gain, delay, leak) == expected


def test_the_transient_is_at_most_mid_run(slow):
    """R38-RE2: at gain 0.002 (3 time constants ~ 1500 frames) the transient is T // 2."""
    run = _with_loop(slow, gain=0.002)
    assert _servo_transient(0.002, 1, 0.0) > slow.times.size // 2
    assert run.transient_frames == run.averaging_start == slow.times.size // 2


def test_a_predictor_run_keeps_the_half(slow):
    """R38-RE4: the servo model is the integrator's; a predictor's run keeps T // 2."""
    run = dataclasses.replace(slow, predictor="ar")
    assert run.transient_frames == run.averaging_start == slow.times.size // 2


class _TooSmall(SimulationResult):
    """The same run, its status read as "closed, SR too small to show it"."""

    @property
    def loop_status(self) -> str:
        return "closed, SR too small to show it: (stand-in)"


def test_sr_too_small_gets_the_servo_transient(slow):
    """R38-RE5: the second status the rule names gets the servo model's transient too."""
    run = _TooSmall(**{f.name: getattr(slow, f.name) for f in dataclasses.fields(slow)})
    assert run.averaging_start == slow.times.size // 2
    assert run.transient_frames == _servo_transient(0.02, 1, 0.0) == 148


@pytest.mark.parametrize("data", [np.float64(148.0), np.array([148, 0], dtype=np.int64)])
def test_a_transient_that_is_not_one_integer_is_not_read(slow, tmp_path, data):
    """R38-HD1: a float or an array in ``transient_frames`` is not a transient: refused.

    Written with h5py over a saved run.h5 (as a file from another writer could hold
    it); the reader keeps the refusal of a result without the dataset.
    """
    import h5py

    from modalinfo.io import LogFormatError, load

    path = slow.save(tmp_path / "run.h5")
    with h5py.File(path, "a") as f:
        del f["transient_frames"]
        f.create_dataset("transient_frames", data=data)
    with pytest.raises(LogFormatError, match="closure transient"):
        load(path, dataset="logs/dm0.residual")
