"""An MI ordering with the raw-value KDE warns of oversmoothing once, not once per mode.

References (outside the code under test): the project's rule "warnings say what and
why, once" (docs/ADVERSARIAL.md, round 16 PART a) and Python's own warnings
machinery (``warnings.catch_warnings(record=True)`` with the ``"default"`` action,
which shows each distinct message once: the messages differed by their numbers, so
six reached the user from one ``order_modes`` call). The data: five independent
normal modes each on a DC offset 1e9 times its spread, a static aberration whose
pooled pixel values are multimodal, where the kernel following the overall spread
oversmooths (Silverman 1986, sec. 3.4.4: the leave-one-out likelihood rises at a
narrower bandwidth).
"""

import warnings

import numpy as np

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.information import BiasRuleWarning
from modalinfo.ordering import order_modes
from modalinfo.telemetry import ModalLog


def test_one_oversmoothing_warning_per_ordering():
    rng = np.random.default_rng(4)
    c = rng.standard_normal((3000, 5)) * [3, 2, 1.5, 1, 0.5]
    log = ModalLog(c + 1e9 * c.std(axis=0), modes=range(2, 7))
    basis = ZernikeBasis(Pupil(16), range(2, 7))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        order_modes(log, basis, "mi_marginal", estimator="kde",
                    estimator_options={"copula": False}, sample_budget=3000, seed=0,
                    n_resamples=0)
    bias = [w for w in caught if issubclass(w.category, BiasRuleWarning)]
    assert len(bias) == 1
    assert "oversmooths" in str(bias[0].message)
    assert "does not repeat the warning" in str(bias[0].message)
