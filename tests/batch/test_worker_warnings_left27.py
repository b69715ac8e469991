"""Batch workers say a warning in the command's one-line form (Leftovers 27-scale, issue 27).

Leftovers 26-rate, Left: the worker processes of ``modalinfo batch``'s ``LocalCluster``
printed a plausibility warning in Python's two-line form with a Dask source line
(``dask/_task_spec.py``), while the command says ``modalinfo batch: warning: ...``.

References (outside the code): the command's form is ``PREFIX: warning: MESSAGE`` on
one line, the message being the warning's ``cli_text`` (the advice for a command's
user); a log whose timestamps are 1000 s apart has a frame rate of 1 / 1000 s = 0.001
Hz, below the 1 Hz of the rate rule, so loading it warns. The workers are other
processes (fd 2 inherited): what they print is read from the test's stderr.
"""

import warnings

import numpy as np
import pytest

pytest.importorskip("distributed")

from modalinfo.common.startup import one_line_format  # noqa: E402
from modalinfo.common.tasks.cluster import open_client  # noqa: E402


def test_a_worker_warns_in_the_commands_one_line_form(tmp_path, capfd, monkeypatch):
    def load_frames(path: str) -> int:  # pickled by value: the workers import no test
        from modalinfo.io import load

        return load(path).n_frames

    x = np.random.default_rng(0).standard_normal((300, 3))
    path = tmp_path / "slow.csv"
    np.savetxt(path, np.column_stack([np.arange(300) * 1000.0, x]), delimiter=",",
               header="time,Z2,Z3,Z4", comments="")
    monkeypatch.setattr(warnings, "formatwarning", one_line_format("modalinfo batch"))
    with open_client(n_workers=2, memory_limit="1GB",
                     dashboard_address=None) as client:
        assert client.gather(client.map(load_frames, [str(path)] * 2, pure=False)) == [300, 300]
    err = capfd.readouterr().err
    lines = [line for line in err.splitlines() if "0.001 Hz" in line]
    assert lines  # each worker that loaded the log said it
    for line in lines:
        assert line.startswith("modalinfo batch: warning: `timestamps` give a frame rate "
                               "of 0.001 Hz")
        assert "check the unit of the file's time column" in line  # the CLI's advice
    assert "UserWarning" not in err and "_task_spec" not in err


def test_a_python_caller_keeps_pythons_form(monkeypatch):
    from modalinfo.common.startup import WARNING_PREFIX_ENV, worker_warning_env

    monkeypatch.setattr(warnings, "formatwarning", lambda *args, **kw: "python's form\n")
    assert worker_warning_env() == {}
    monkeypatch.setattr(warnings, "formatwarning", one_line_format("closedloop sweep"))
    assert worker_warning_env() == {WARNING_PREFIX_ENV: "closedloop sweep"}
