"""DataFrame column names that contradict ``modes`` (adversarial round 42 PART a, M03 M04 M20).

``ModalLog(df, modes=[2, ..., 7])`` with columns named ``Z4, Z2, Z3, Z7, Z5, Z6`` labelled
the ``Z4`` column Z2 without a word: the names were read only when ``modes`` was missing.
Reference: the DataFrame's own column names (pandas), which state Noll indices; a log
must not label a column another mode than its name states.
"""

import numpy as np
import pandas as pd
import pytest

from modalinfo.telemetry import ModalLog

RNG = np.random.default_rng(42)
DATA = RNG.standard_normal((200, 6))
PERM = [4, 2, 3, 7, 5, 6]


@pytest.mark.parametrize("columns, modes", [
    ([f"Z{j}" for j in PERM], list(range(2, 8))),      # M04: Z-labels, another order
    (PERM, list(range(2, 8))),                          # M03: int labels, another order
    (list(range(2, 8)), list(range(3, 9))),             # M20: int labels, other modes
])
def test_contradicting_names_refused(columns, modes):
    frame = pd.DataFrame(DATA, columns=columns)
    with pytest.raises(ValueError, match=r"`coeffs` is a DataFrame whose columns are named"):
        ModalLog(frame, modes=modes)


def test_reordered_labels_refused_with_labels_convention():
    frame = pd.DataFrame(DATA[:, :3], columns=["tip", "tilt", "focus"])
    with pytest.raises(ValueError, match="disagree"):
        ModalLog(frame, modes=["tilt", "tip", "focus"], convention="labels")


@pytest.mark.parametrize("columns, modes, convention", [
    ([f"Z{j}" for j in PERM], PERM, "noll"),            # names and modes agree
    (PERM, PERM, "noll"),
    (["tip", "tilt", "focus", "a", "b", "c"], list(range(2, 8)), "noll"),  # free names
    (list(range(6)), list(range(2, 8)), "noll"),        # pandas' default names
    ([f"A{j}" for j in range(1, 7)], list(range(1, 7)), "ansi"),
    (["t1", "t2", "t3", "t4", "t5", "t6"], ["u1", "u2", "u3", "u4", "u5", "u6"], "labels"),
])
def test_agreeing_or_free_names_accepted(columns, modes, convention):
    frame = pd.DataFrame(DATA, columns=columns)
    log = ModalLog(frame, modes=modes, convention=convention)
    assert list(log.modes) == list(modes)
    np.testing.assert_array_equal(log.coeffs, DATA)
