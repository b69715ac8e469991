"""Round 2 of issue 27's adversarial inputs against ``closedloop``: the refusals fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 2, issue 27".

Reference: the dispatcher's documented contract (``modalinfo.common.cli.dispatch``):
one line on stderr naming the command-line option, exit 2, no traceback, nothing
written over an existing file (its bytes are compared).
"""

from __future__ import annotations

import pytest

from closedloop.cli import main


@pytest.mark.parametrize("argv, option", [
    (["config", "--config", "{dir}"], "--config"),
    (["run", "--config", "{txt}", "--duration", "0.001", "--quiet"], "--config"),
    (["config", "--preset", "table1", "--out", "{txt}"], "--out"),
])
def test_config_paths_without_toml_or_json_name_the_option(tmp_path, capsys, argv, option):
    # Before: "`path` must end in .toml or .json" (the library's argument name).
    (tmp_path / "d.npz").mkdir()
    txt = tmp_path / "existing.txt"
    txt.write_bytes(b"precious")
    argv = [a.format(dir=tmp_path / "d.npz", txt=txt) for a in argv]
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert f"{option} must end in .toml or .json" in err, err
    assert txt.read_bytes() == b"precious"
