"""``forecast --max-seconds``'s refusal says what the option takes (fix49-c, item 4).

The library's refusal ends "or raise `max_seconds` (None: no limit)"; on the command
line it read "raise --max-seconds (None: no limit)", and ``--max-seconds None`` (or
``inf``, or 0) is refused by the option itself (stop 55's note). Reference: argparse's
own parse of the value the message says it accepts, and the command's refusal of
``inf`` ("--max-seconds must be finite").
"""

from __future__ import annotations

from .conftest import exit_code


def test_the_refusal_names_what_the_option_takes(make_small_log, capsys):
    log = make_small_log(300)
    assert exit_code(["forecast", log, "--max-seconds", "1e-9"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert "more than --max-seconds=1e-09" in err, err
    assert "None" not in err and "no limit" not in err and "`max_seconds`" not in err, err
    assert "raise --max-seconds (CPU seconds: a finite number above 0)" in err, err
    # what it says the option takes is what it takes: neither inf ("no limit") nor 0
    for value, words in (("inf", "must be finite"), ("0", "must be > 0")):
        assert exit_code(["forecast", log, "--max-seconds", value]) == 2
        assert words in capsys.readouterr().err
