"""Round 2 of issue 27's adversarial inputs against ``closedloop``: the refusals fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 2, issue 27".

Reference: the dispatcher's documented contract (``modalinfo.common.cli.dispatch``):
one line on stderr naming the command-line option, exit 2, no traceback, nothing
written over an existing file (its bytes are compared).
"""

from __future__ import annotations

import pytest

from closedloop.cli import main


@pytest.mark.parametrize("argv, needle", [
    (["config", "--config", "{dir}"], "--config must end in .toml or .json"),
    (["run", "--config", "{txt}", "--duration", "0.001", "--quiet"],
     "--config must end in .toml or .json"),
    (["config", "--preset", "table1", "--out", "{txt}"], "--out must end in .toml or .json"),
    (["config", "--preset", "table1", "--fmt", "json", "--out", "{toml}"],
     "--fmt json contradicts --out"),
])
def test_config_paths_are_refused_naming_the_option(tmp_path, capsys, argv, needle):
    # Before: "`path` must end in .toml or .json" (the library's argument name), and
    # `--fmt json --out cfg.toml` wrote TOML, ignoring --fmt without a word.
    (tmp_path / "d.npz").mkdir()
    txt = tmp_path / "existing.txt"
    txt.write_bytes(b"precious")
    toml = tmp_path / "cfg.toml"
    argv = [a.format(dir=tmp_path / "d.npz", txt=txt, toml=toml) for a in argv]
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    assert needle in err, err
    assert txt.read_bytes() == b"precious" and not toml.exists()


def test_config_fmt_on_stdout_and_matching_out_still_work(tmp_path, capsys):
    assert main(["config", "--preset", "table1", "--fmt", "json"]) == 0
    assert capsys.readouterr().out.lstrip().startswith("{")
    assert main(["config", "--preset", "table1", "--fmt", "json", "--out",
                 str(tmp_path / "c.json")]) == 0
    assert (tmp_path / "c.json").read_text().lstrip().startswith("{")
