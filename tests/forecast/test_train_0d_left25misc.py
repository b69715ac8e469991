"""``evaluate(train=...)`` takes a 0-d array or a NumPy scalar as its number.

Reference, from outside the code: a 0-d array holds one number (``np.array(x)[()]`` is
``x``), so ``train=np.array(300)`` must split the series where ``train=300`` does, and
``train=np.array(0.5)`` where ``0.5`` does; a 0-d bool, complex or string array stays
refused as ``True`` is. Before, ``train`` was checked with ``isinstance(train,
numbers.Real)`` and refused a 0-d array (left25-api's "Left" list).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.forecast import LinearPredictor, evaluate


def _ev(train):
    x = np.random.default_rng(4).standard_normal((600, 2))
    return evaluate({"ar": LinearPredictor(a=0.5, b=0.0)}, x, train=train, horizons=[1])


@pytest.mark.parametrize("plain,wrapped", [(300, np.array(300)), (300, np.int32(300)),
                                           (0.5, np.array(0.5)), (0.5, np.float32(0.5))])
def test_train_takes_0d_arrays(plain, wrapped):
    assert _ev(wrapped).n_train == _ev(plain).n_train


@pytest.mark.parametrize("bad", [np.array(True), np.array(0.5 + 0j), np.array("300")])
def test_train_still_refuses_non_numbers(bad):
    with pytest.raises(TypeError, match="`train`"):
        _ev(bad)
