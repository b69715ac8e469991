"""`evaluate` names the rule a training set breaks (adversarial round 10 PART a).

Reference: the protocol's two counts, training frames >= 1 and test frames >= max(h) + 1,
for T = 300 frames and horizons 1..10: train = 1e-9 rounds to 0 training frames (the
first rule), train = 295 leaves 5 test frames (the second).
"""

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, evaluate

X = np.random.default_rng(0).standard_normal((300, 2))


def test_no_training_frame_is_named_as_such():
    with pytest.raises(ValueError, match=r"at least 1 training frame; got 1e-09 \(0 of the 300"):
        evaluate([LinearPredictor()], X, train=1e-9)


def test_too_few_test_frames_keep_their_message():
    with pytest.raises(ValueError, match=r"leave at least max\(horizons\) \+ 1 = 11 test"):
        evaluate([LinearPredictor()], X, train=295)
