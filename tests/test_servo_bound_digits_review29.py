"""The refused gain's bound: 4 decimals where they put the gain above it, else the rule (review29).

Round 29 S1 / S2 (modalinfo/servo.py:252 / 254, ``_shown_bound``, fixes 45-c): its
docstring promises "4 decimals where they do (round 3's form); else as many as it takes,
with the rule". The round 45 tests used delay 1 frame (limit 1: 4 decimals round up to
1.0000 for every gain below it, so 12+ digits) and gain 1.5 (4 decimals enough). Planted
slips passed them: "<" for "<=" (a gain equal to its 4-decimal bound given 5 digits and
the rule) and the rule dropped at 5 digits. At delay 1.25 frames the limit 0.9442719...
rounds up at 4 decimals (0.9443) and down at 5 (0.94427). References, from outside the
code: Python's ``format`` of the limit at 4 and 5 decimals, by hand; the gain written
0.9443, the 4-decimal bound itself.
"""

import re

import pytest

from modalinfo.servo import check_stable, max_stable_gain


def _bound_shown(gain: float) -> str:
    with pytest.raises(ValueError, match="makes the loop unstable") as exc:
        check_stable(gain, 1.25, 1.0)
    return re.search(r"the loop is stable for gain < (.*)\.$", str(exc.value)).group(1)


def test_a_gain_equal_to_the_four_decimal_bound_keeps_round_3s_form():
    limit = max_stable_gain(1.25, 1.0)
    assert f"{limit:.4f}" == "0.9443" and limit < 0.9443  # refused, by hand
    assert _bound_shown(0.9443) == "0.9443"  # 0.9443 is not below 0.9443: 4 decimals do


def test_five_decimals_carry_the_rule():
    limit = max_stable_gain(1.25, 1.0)
    assert f"{limit:.4f}" == "0.9443" and f"{limit:.5f}" == "0.94427"  # by hand
    shown = _bound_shown(limit)  # the limit itself: 0.9443 would read as above it
    assert shown.startswith("0.94427 (the limit ")
    assert shown.endswith(" less its 1e-12 relative accuracy)")
    assert float(shown.split()[0]) <= limit
