"""Round 18 PART b: the README's ``modalinfo batch`` examples pass the option checks.

Reference: the README itself, run as written (help text and examples as a contract).
Each README line starting ``modalinfo batch`` is run with its input replaced by a
missing path and its output by a temporary folder: the only refusal allowed is the
missing input (found after every option is checked); a refusal of the options
themselves (round 18 E02: ``--set forecast.horizon=10`` without ``--analyses
forecast``) means the example does not run as written.
"""

import re
import shlex
from pathlib import Path

import pytest

from modalinfo.cli import main

README = Path(__file__).resolve().parents[2] / "README.md"
LINES = [ln.split("#")[0].strip() for ln in README.read_text(encoding="utf-8").splitlines()
         if ln.startswith("modalinfo batch ")]


def test_readme_has_batch_examples():
    assert len(LINES) >= 3


@pytest.mark.parametrize("line", LINES)
def test_readme_batch_example_options_accepted(line, tmp_path, capsys):
    argv = shlex.split(line)[1:]
    argv[1] = str(tmp_path / "missing")  # the INPUT
    argv[argv.index("--out") + 1] = str(tmp_path / "out")
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert re.search(r"input '.*missing' is neither", err), err
