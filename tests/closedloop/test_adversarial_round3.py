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

from .conftest import small


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


def _write(tmp_path, name, data: bytes):
    path = tmp_path / name
    path.write_bytes(data)
    return path


def test_a_json_key_given_twice_is_refused(tmp_path):
    # Before: {"gain": 0.5, "gain": 0.3} loaded with gain 0.3 (JSON keeps the last);
    # TOML refuses a repeated key, so the two formats now agree.
    from closedloop.config import load_config

    text = json.dumps(presets.get("table1").to_dict()).replace('"gain": 0.5',
                                                               '"gain": 0.5, "gain": 0.3')
    path = _write(tmp_path, "c.json", text.encode())
    with pytest.raises(ValueError, match=r"c.json': key 'gain' given twice in one JSON "
                                         r"object \(0.5 and 0.3\)"):
        load_config(path)


def test_a_toml_file_with_a_byte_order_mark_loads(tmp_path):
    # Before: "not valid TOML: Invalid statement (at line 1, column 1)" for a file saved
    # by a Windows editor; the same bytes without the mark load.
    from closedloop.config import config_text, load_config

    text = config_text(presets.get("table1")).encode()
    plain = load_config(_write(tmp_path, "a.toml", text))
    assert load_config(_write(tmp_path, "b.toml", b"\xef\xbb\xbf" + text)) == plain


def test_an_obscuration_leaving_no_valid_subaperture_is_refused(capsys, tmp_path):
    # Before: IndexError traceback in the reconstructor (no measurement at all): 8 x 8
    # subapertures on a 0.95 obscured pupil are each less than half lit.
    from closedloop.model import LoopModel

    d = small().to_dict()
    d["telescope"]["obscuration"] = 0.95
    with pytest.raises(ValueError, match=r"`wfss\[0\].n_subapertures` = 8 leaves no valid "
                                         r"subaperture .*obscuration = 0.95"):
        LoopModel(SimulationConfig.from_dict(d))


def test_a_sweep_seed_beyond_int64_is_refused_before_any_run(tmp_path):
    # Before: OverflowError traceback from the cluster's worker (seed 2**63).
    from closedloop.sweep import sweep_specs

    with pytest.raises(ValueError, match=r"grid `seeds` must be ints <= 2\*\*63 - 1 .*got "
                                         r"9223372036854775808"):
        sweep_specs({"preset": "table1", "duration": 0.01, "seeds": [0, 2**63]})
