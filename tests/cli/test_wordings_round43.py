"""One-line wordings of round 43 PART b (d14, c28, g10): what the messages promise.

References: the docs' promise checked on the output itself (d14: the head line names
"last columns: modes to reach each target" only when such columns follow, counted here
from the header row), the command's own table (c28: persistence and mean rows are in
every forecast table, so asking for them is not an "unknown predictor"), and the first
line of paper_figures' report.md (g10: "# modalinfo: regenerated figures ..." is text,
not a JSON header).
"""

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import LogFormatError, load, save
from modalinfo.telemetry import ModalLog


@pytest.fixture
def log_path(tmp_path):
    rng = np.random.default_rng(0)
    log = ModalLog(rng.standard_normal((400, 6)), rate=1000.0, modes=list(range(2, 8)),
                   units="rad")
    return save(log, tmp_path / "s.npz")


def test_d14_no_target_promise_without_targets(log_path, capsys):
    assert main(["fitting-error", str(log_path)]) == 0
    out = capsys.readouterr().out
    head = next(x for x in out.splitlines() if x.startswith("fitting error dPhi"))
    assert "last columns" not in head
    assert main(["fitting-error", str(log_path), "--target", "0.5"]) == 0
    out = capsys.readouterr().out
    head = next(x for x in out.splitlines() if x.startswith("fitting error dPhi"))
    assert "last columns: modes to reach each target" in head
    assert "<=0.5" in out  # the promised column is there


def test_c28_persistence_is_a_baseline_not_unknown(log_path, capsys):
    for name in ("persistence", "mean"):
        assert main(["forecast", str(log_path), "--predictors", name]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "unknown predictor" not in err
        assert "always evaluated" in err and "baselines" in err and repr(name) in err


def test_g10_report_fed_back_is_a_text_file(tmp_path):
    report = tmp_path / "report.md"
    report.write_text("# modalinfo: regenerated figures of Stangalini et al., LOST MCAO "
                      "simulations\n\nPython 3.11.7, x86_64; made in 1 s.\n")
    with pytest.raises(LogFormatError) as info:
        load(report)
    msg = str(info.value)
    assert "not a modalinfo CSV header (a text file" in msg and "Expecting value" not in msg
