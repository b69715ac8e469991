"""The closure transient of a loop "still converging", from the servo model (fix56-c).

fix54-e gave a run "closed, still converging" its whole first half as the transient the
quality pass leaves out (``averaging_start`` = T // 2). kaos at gain 0.02 (0.5 s, 1000
frames, seed 1) is such a run; its integrator's time constant is 48.5 frames, and its
residual reaches its level by frame ~100 (50-frame means of the field-mean residual
20.8, 4.6, 2.8 rad^2, then 2.8-5.4 to the end). Its transient is now the first command's
frame plus 3 time constants: 2 + ceil(3 x 48.48) = 148 frames, not 500.

References: the time constant from the analytic pole of kaos' loop (one frame of delay,
full exposure, no leak: the roots of ``z**2 - z + g``), the first command's frame from
the timing (frame k sees a command once (k + 1) T > T + delay: frame 2); the residual
itself (numpy means of ``residual_variance``: the first time constant after the first
command is above 3 times the second half's level, the frames from the transient to
mid-run within a factor 2 of it; deterministic, seed 1); the run.h5 file written by
``save`` (its dataset ``transient_frames`` read with h5py) and read back by
``SimulationResult.load`` (equal, checksums verified) and by ``modalinfo.io.load`` and
``modalinfo info`` (the residual's and commands' key, none on the POL, the coefficients
bit for bit, "frames 0-147 not assessed"); a file without the dataset (as saved before)
keeps fix55-c's refusal. Each test but that guard fails before fix56-c (the property and
the dataset did not exist; the transient was 500).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from closedloop import SimulationResult, presets, simulate
from modalinfo.cli import main as modalinfo_main
from modalinfo.io import LogFormatError, load

GAIN = 0.02


@pytest.fixture(scope="module")
def slow():
    base = presets.get("kaos")
    cfg = dataclasses.replace(base, loop=dataclasses.replace(base.loop, gain=GAIN))
    return simulate(cfg, 0.5, seed=1, progress=False)


def _expected(result) -> int:
    loop = result.config.loop
    assert (loop.delay_frames, loop.integration_frames, loop.leak) == (1.0, 1.0, 0.0)
    r = (1 + math.sqrt(1 - 4 * GAIN)) / 2  # the slower root of z**2 - z + g
    first_command = 2  # (k + 1) T > T + 1 frame of delay
    return first_command + math.ceil(3 * -1 / math.log(r))


def test_still_converging_transient_is_three_time_constants(slow):
    assert slow.loop_status.startswith("closed, still converging")
    n = slow.times.size
    assert slow.averaging_start == n // 2  # the averages keep the second half
    assert slow.transient_frames == _expected(slow) == 148


def test_the_residual_has_reached_its_level_there(slow):
    v = slow.residual_variance.mean(axis=1)  # field mean per frame [rad^2]
    n, t = v.size, slow.transient_frames
    level = v[n // 2:].mean()
    tau = (t - 2) // 3
    assert v[2:2 + tau].mean() > 3 * level  # a transient really there
    assert v[t:n // 2].mean() < 2 * level   # and over by the transient's end


def test_run_h5_round_trips_and_its_logs_read_with_it(slow, tmp_path, capsys):
    import h5py

    path = slow.save(tmp_path / "run.h5")
    with h5py.File(path, "r") as f:
        assert f["transient_frames"][()] == 148
    back = SimulationResult.load(path)  # checksums verified, the dataset among them
    assert back == slow
    for name in slow.logs:
        assert back.logs[name].metadata == slow.logs[name].metadata
        np.testing.assert_array_equal(back.logs[name].coeffs, slow.logs[name].coeffs)
    for name in ("residual", "commands", "pol"):
        log = load(path, dataset=f"logs/dm0.{name}")
        np.testing.assert_array_equal(log.coeffs, slow.logs[f"dm0.{name}"].coeffs)
        expected = None if name == "pol" else 148  # the turbulence has no transient
        assert log.metadata.get("transient_frames") == expected, name
    assert modalinfo_main(["info", str(path), "--dataset", "logs/dm0.residual"]) == 0
    out = capsys.readouterr().out
    assert "frames 0-147 not assessed" in out


def test_a_result_saved_without_it_keeps_the_refusal(slow, tmp_path):
    import h5py

    path = slow.save(tmp_path / "old.h5")
    with h5py.File(path, "a") as f:  # as a run.h5 saved before fix56-c
        del f["transient_frames"]
    with pytest.raises(LogFormatError, match="closure transient"):
        load(path, dataset="logs/dm0.residual")
    assert load(path, dataset="logs/dm0.pol").n_frames == slow.times.size


def test_a_closed_run_keeps_its_closure(tmp_path):
    run = simulate(presets.get("kaos"), 0.5, seed=1, progress=False)
    assert run.closed
    assert run.transient_frames == run.averaging_start == run.closure_index
