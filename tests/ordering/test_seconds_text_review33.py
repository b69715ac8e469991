"""``seconds_text`` states whole seconds from 10 s (review33, mutation round 33).

Reference: the docstring's rule ("whole seconds from 10 s, two significant figures
below"), i.e. Python's ``round`` of the estimate, read back from the message with
``float``. fix50-b's file checked 42.4 and 7,200 s only, where two significant figures
and whole seconds print alike (42) or the plant's threshold was not crossed; between 100
and 1,000 s they differ (123.4: "123" against "1.2e+02").
"""

from __future__ import annotations

import re

import pytest

from modalinfo.ordering import cost


@pytest.mark.parametrize("seconds", [10.4, 123.4, 987.0, 4321.6])
def test_whole_seconds_from_ten(seconds):
    text = cost.seconds_text(seconds)
    shown = re.search(r"is estimated at (\S+) s of CPU or more", text).group(1)
    assert float(shown) == round(seconds)
    assert "e" not in shown
