"""Round 39 PART a, M30: ``compare_orderings`` of a ``convention="labels"`` log.

Before, it raised "ValueError: invalid literal for int() with base 10: 'Z2'" (no argument
named) from the basis recipe; ``basis_for_log`` refused such a log, but without naming
``log``. Reference: the docs' rule (a refusal names the argument and what was wrong); a
labelled log has no Zernike indices, so the Zernike / K-L bases cannot be built for it.
"""

import numpy as np
import pytest

from modalinfo.ordering.compare import basis_for_log, compare_orderings
from modalinfo.telemetry import ModalLog


def _labels_log():
    x = np.random.default_rng(0).normal(size=(300, 5))
    return ModalLog(x, rate=1000.0, modes=[f"Z{j}" for j in range(2, 7)],
                    convention="labels")


@pytest.mark.parametrize("specs", ["zernike:standard", "zernike:variance", "kl-data:pca"])
def test_compare_orderings_refuses_a_labels_log_naming_it(specs):
    with pytest.raises(ValueError, match=r"`log` has convention='labels'"):
        compare_orderings(_labels_log(), specs)


@pytest.mark.parametrize("kind", ["zernike", "kl-theory", "kl-data"])
def test_basis_for_log_refuses_a_labels_log_naming_it(kind):
    with pytest.raises(ValueError, match=r"`log` has convention='labels'.*order_modes"):
        basis_for_log(kind, _labels_log())
