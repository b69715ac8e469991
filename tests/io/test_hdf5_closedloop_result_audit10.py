"""A closedloop result given as a log is refused in one line, naming the way to its logs
(audit 10, feedback, row cli-h5-result-dataset).

Reference: the command-line contract (exit 2, one line on stderr) and the file's own
``format`` attribute, ``closedloop-result``, that ``SimulationResult.save`` writes. Before,
``modalinfo info r.h5 --dataset logs/dm0.pol/coefficients`` called the file "corrupt"
(its log datasets carry modalinfo's attributes but the file has no log header).
Since fix55-c the pseudo-open-loop log is read there (tests/cli/test_messages_fix55c.py); a
closed loop's residual is read since fix56-c from a file that holds its closure transient
(the dataset ``transient_frames``, tests/closedloop/test_transient_servo_fix56c.py) and
still refused from one saved before it, as here (the dataset deleted).
"""

import pytest

from closedloop import simulate
from modalinfo.cli import main
from modalinfo.io import LogFormatError, load

from ..closedloop.conftest import tiny_actuator_config  # the closedloop tests' small loop


@pytest.fixture(scope="module")
def result_file(tmp_path_factory):
    import h5py

    path = simulate(tiny_actuator_config(), 0.005, seed=0).save(
        tmp_path_factory.mktemp("r") / "r.h5")
    with h5py.File(path, "a") as f:  # as a result saved before fix56-c
        del f["transient_frames"]
    return path


@pytest.mark.parametrize("extra", [[], ["--dataset", "logs/dm0.residual/coefficients"]])
def test_command_refuses_in_one_line(result_file, capsys, extra):
    assert main(["info", str(result_file), *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and ("closedloop result" in err or "closed loop" in err)
    assert "closedloop export" in err


def test_api_refuses(result_file):
    with pytest.raises(LogFormatError, match="closedloop result"):
        load(result_file)
    with pytest.raises(LogFormatError, match="residual of a closed loop"):
        load(result_file, dataset="logs/dm0.residual/coefficients")
