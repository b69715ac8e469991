"""A batch fitting_error row names the unit of its curves (`error_units`).

Adversarial round 41 PART b, issue 27 (row B03): a night's batch of fitting errors wrote
`total_variance` 0.0373 for a log in rad beside the row's `units` column "rad": the
value is in waves^2 (the default `fitting_error.units`), 1.47 rad^2 by `fitting-error
--error-units rad2`. Reference, outside the code: numpy's sum of the log's mean squares
over (2 pi)^2 (rad^2 -> waves^2), within the 64-pixel pupil's Gram error (the command's
own note: a few %).
"""

from __future__ import annotations

import numpy as np

from modalinfo.batch.analyses import DEFAULTS, _fitting_error
from modalinfo.telemetry import ModalLog


def test_the_row_names_the_unit_of_total_variance():
    x = np.random.default_rng(41).standard_normal((400, 9)) * 0.3
    log = ModalLog(x, rate=1000.0, modes=list(range(2, 11)), units="rad", wavelength=1e-6)
    params = {**DEFAULTS["fitting_error"], "orderings": "zernike:standard", "fraction": None}
    row = _fitting_error(log, params)
    assert row["error_units"] == "waves2"
    waves2 = float(np.sum(np.mean(x ** 2, axis=0))) / (2 * np.pi) ** 2
    assert abs(row["total_variance"] / waves2 - 1) < 0.05
