"""``evaluate`` with a list holding a non-predictor names its position and the fix.

Round 40 PART a, E01. Reference: the documented ``predictors`` argument ("a dict of name
-> Predictor or a list of Predictor") and ``make_predictor``'s preset names
(``PRESETS``). Before: ``evaluate(["linear-ls"], log)`` said "`predictors['str']` must
be a Predictor; got str.", a key made of the value's type name.
"""

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, evaluate
from modalinfo.telemetry import ModalLog


def _log():
    return ModalLog(np.random.default_rng(0).standard_normal((200, 2)), rate=1000.0)


def test_a_preset_name_in_the_list_is_refused_by_position_with_the_fix():
    with pytest.raises(TypeError) as err:
        evaluate([LinearPredictor(), "linear-ls"], _log(), horizons=(1,))
    text = str(err.value)
    assert "`predictors[1]`" in text and "make_predictor('linear-ls')" in text


def test_another_object_is_refused_by_position():
    with pytest.raises(TypeError, match=r"`predictors\[0\]` must be a Predictor; got int 3"):
        evaluate([3], _log(), horizons=(1,))
