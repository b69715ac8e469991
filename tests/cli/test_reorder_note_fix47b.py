"""reorder's cost note says what its estimate is (fixes 47-b, round 46 PART a A03a / A03c).

``modalinfo.ordering.cost.least_ordering_seconds`` is a lower bound (its module notes):
the library's refusals and warnings say "is estimated at N s of CPU or more (a lower
bound)" since fixes 46-a, while the command line's note still said "is estimated at N s
of CPU". Reference: the library's wording, ``cost.seconds_text``, and the stated
estimate (monkeypatched, so that the note does not depend on the machine).
"""

from __future__ import annotations

from modalinfo.ordering import cost

from .conftest import exit_code


def test_reorders_note_says_what_the_estimate_is(make_small_log, capsys, monkeypatch):
    # the command line's note said "is estimated at 90 s of CPU", read as a forecast of a
    # lower bound (cmd_reorder.check_mi_time); now the library's words (cost.seconds_text)
    path = make_small_log(200)
    monkeypatch.setattr(cost, "least_ordering_seconds", lambda *a, **k: (90.0, 7))
    argv = ["reorder", path, "--budget", "500", "--pupil-pixels", "16", "--method",
            "mi_marginal", "--resamples", "0"]
    assert exit_code(argv) == 0
    notes = [line for line in capsys.readouterr().err.splitlines() if "estimated" in line]
    assert len(notes) == 1 and notes[0].startswith("modalinfo reorder: note: ")
    assert f"modes) {cost.seconds_text(90.0)}; " in notes[0]
    assert "90 s of CPU or more (a lower bound)" in notes[0]
