"""A refusal never states its CPU estimate as 0 s, nor as a number at or below its limit.

Stop 56 left (fix49-c): ``seconds_text`` rounded to whole seconds, so ``forecast
--max-seconds 1e-9`` was refused as "estimated at 0 s of CPU or more ... more than
--max-seconds=1e-09", and an ordering refused at a limit of 0.115 s "estimated at 0 s".
Reference: the numbers printed in the message, read back with ``float``: the estimate
within 5 % of the one passed (two significant figures), above 0, and above the limit
as printed (the command line's ``forecast --max-seconds 1e-9``:
tests/cli/test_forecast_max_seconds_fix50b.py).
"""

from __future__ import annotations

import re

import pytest

from modalinfo.ordering import cost

NUMBER = r"([0-9][0-9.]*(?:e[-+][0-9]+)?)"


def _estimate(message: str) -> float:
    return float(re.search(rf"is estimated at {NUMBER} s of CPU or more", message).group(1))


@pytest.mark.parametrize("seconds", [2e-6, 3.7e-4, 0.0262, 0.5, 8.4, 9.96, 42.4, 7200.0])
def test_the_estimate_keeps_two_significant_figures(seconds):
    shown = _estimate(cost.seconds_text(seconds))
    assert shown > 0
    assert abs(shown - seconds) <= (0.05 * seconds if seconds < 10 else 0.5)


@pytest.mark.parametrize(("seconds", "limit"), [(2e-6, 1e-9), (8.4, 8.35), (42.4, 42.3),
                                                (0.0123, 0.012), (0.12, 0.115239),
                                                (1.000001, 1.0)])
def test_a_refusal_reads_above_its_limit(seconds, limit):
    what = f"the work {cost.seconds_text(seconds)}"
    with pytest.raises(ValueError, match="more than `max_seconds`") as exc:
        cost.check_ordering_seconds(seconds, what, "do less", limit)
    message = str(exc.value)
    printed_limit = float(re.search(rf"`max_seconds`={NUMBER};", message).group(1))
    assert _estimate(message) > printed_limit, message
    assert _estimate(message) > 0

