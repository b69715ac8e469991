"""Round 3 of issue 27's adversarial inputs against ``closedloop``: the refusals fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 3, issue 27".

References: the stability law of the sampled integrator ``c[k] = c[k-1] + g m[k]``
whose command reaches the WFS ``n`` whole frames after its measurement,
``1 - z**-1 + g z**-n = 0``: stable for ``g < 2 sin(pi / (2 (2 n - 1)))`` (Madec 1999,
in *Adaptive Optics in Astronomy*, ch. 6), written out here, not taken from
``modalinfo.servo``: n = 1 (no delay, full exposure) gives 2, n = 2 (one frame of
delay) gives 1, n = 3 gives 2 sin(pi / 10) = 0.618...; and the dispatcher's contract
(one line on stderr naming the key, exit 2, no traceback).
"""

from __future__ import annotations

import json
import math

import pytest

from closedloop import presets
from closedloop.cli import main
from closedloop.config import SimulationConfig


def _loop(gain: float, delay_frames: int) -> dict:
    d = presets.get("table1").to_dict()
    d["loop"].update(time_step=1e-3, integration_time=1e-3, delay=delay_frames * 1e-3,
                     gain=gain)
    return d


@pytest.mark.parametrize("delay_frames", [0, 1, 2])
def test_integrator_gain_is_refused_at_its_stability_limit(delay_frames):
    # Before: `gain = 3` loaded and printed by `closedloop config` (only `run` refused it).
    n = delay_frames + 1
    limit = 2.0 * math.sin(math.pi / (2 * (2 * n - 1)))
    SimulationConfig.from_dict(_loop(limit * (1 - 1e-6), delay_frames))  # accepted
    for gain in (limit * (1 + 1e-6), 3.0):
        with pytest.raises(ValueError) as info:
            SimulationConfig.from_dict(_loop(gain, delay_frames))
        message = str(info.value)
        assert message.startswith(f"`loop.gain` = {gain} makes the loop unstable"), message
        assert f"stable for gain < {limit:.4f}" in message, message


def test_config_command_refuses_an_unstable_gain_in_one_line(tmp_path, capsys):
    path = tmp_path / "c.json"
    path.write_text(json.dumps(_loop(3.0, 0)))
    out = tmp_path / "out.toml"
    try:
        code = main(["config", "--config", str(path), "--out", str(out)])
    except SystemExit as exc:
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert "`loop.gain` = 3.0 makes the loop unstable" in err and "gain < 2.0000" in err
    assert not out.exists()
