"""``modalinfo select`` tells the user of a first step estimated at tens of seconds.

Reference (outside the code): audit 9-time's record (docs/ADVERSARIAL.md, issue 27):
``--method ksg`` ran 9.6 min without a word, and its case of 54 candidates x 200 on
398 rows was estimated at 46 s (27.8 s measured). A wait of half a minute is one the
command must announce before the work, and a second or two is not (every gaussian
search, the default). The estimate is replaced here (``selection.first_step_seconds``)
and the search stopped where it would begin, so no test waits.

Planted bug R8-52 (docs/MUTATION.md, round 8): the note's threshold raised from 10 s to
100 s left the audit's 46 s case silent; ``test_cli_select.py`` only tried estimates of
minutes.
"""
from __future__ import annotations

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


@pytest.mark.parametrize("seconds, told", [(46.0, True), (27.8, True), (1.0, False)])
def test_a_half_minute_first_step_is_announced(tmp_path, capsys, monkeypatch, seconds, told):
    from modalinfo.information import selection

    rng = np.random.default_rng(3)
    path = tmp_path / "log.npz"
    save(ModalLog(rng.standard_normal((400, 4)), rate=1e3, modes=[2, 3, 4, 5]), path)
    monkeypatch.setattr(selection, "first_step_seconds", lambda *a, **k: seconds)

    def stop(*args, **kwargs):  # the note must come before the search
        raise SystemExit(5)

    monkeypatch.setattr(selection, "_greedy_search", stop)
    with pytest.raises(SystemExit) as exc:
        main(["select", str(path), "--target", "Z5", "--method", "ksg", "--no-intervals"])
    assert exc.value.code == 5
    err = capsys.readouterr().err
    assert ("note: --method ksg scores" in err) is told, err
    if told:
        assert f"about {seconds:.0f} s of CPU" in err
