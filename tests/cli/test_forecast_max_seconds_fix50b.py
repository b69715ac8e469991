"""``forecast --max-seconds 1e-9`` is refused with an estimate above 1e-09 s, not "0 s".

Stop 56 left (fix49-c): the refusal read "estimated at 0 s of CPU or more ... more than
--max-seconds=1e-09" (``seconds_text`` rounded to whole seconds). Reference: the
message's own two numbers read back with ``float`` (the library's rule:
tests/ordering/test_seconds_text_fix50b.py).
"""

from __future__ import annotations

import re

from .conftest import exit_code


def test_the_forecast_refusal_at_1e_9(make_small_log, capsys):
    log = make_small_log(300)
    assert exit_code(["forecast", log, "--max-seconds", "1e-9"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert "estimated at 0 s" not in err, err
    estimate = float(re.search(r"is estimated at ([0-9][0-9.]*(?:e[-+][0-9]+)?) s of CPU",
                               err).group(1))
    assert estimate > 1e-9 and "more than --max-seconds=1e-09" in err, err
