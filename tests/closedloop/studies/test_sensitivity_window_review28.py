"""``sensitivity._row``: the FoV on the run's own window whatever ``start`` (review28, round 28).

``_row``'s comment: the SR means from ``start`` if given, "the FoV diameter always on the
run's own window (Figure 4's and SimulationResult.summary's), also for its rescaled
wavelengths". Planted bug R28-W2 (the rescaled run's FoV read from ``start``) escaped
``test_mutation_gaps_sensitivity.py`` and ``test_solar_plumbing.py``: no caller passes
both a wavelength scale and a window today. References: Marechal (SR = exp(-variance))
by hand on the variances written here, and the FoV of a run built here with the rescaled
variance and its own closure (``SimulationResult.corrected_fov_diameter``).
"""

import dataclasses

import numpy as np
import pytest

from closedloop import presets
from closedloop.config import FieldConfig
from closedloop.result import SimulationResult
from closedloop.studies import sensitivity as sens

FIELD = FieldConfig(size=60.0, n_points=3)


def _run():
    cfg = presets.get("table1").replace(field=FIELD)
    half = cfg.field.size / 2
    v = np.linspace(-half, half, cfg.field.n_points)
    yy, xx = np.meshgrid(v, v, indexing="ij")
    pattern = 0.2 + 0.7 * ((xx ** 2 + yy ** 2) / half ** 2).ravel()
    wobble = 1.0 + 0.02 * np.array([0, 1, -1, 0, 1, -1, 0, 1, -1])
    variance = np.vstack([np.full((3, pattern.size), 8.0), np.outer(wobble, pattern)])
    return SimulationResult(config=cfg, seed=0, predictor="none",
                            times=np.arange(1, variance.shape[0] + 1) * cfg.loop.time_step,
                            directions=np.column_stack([xx.ravel(), yy.ravel()]),
                            residual_variance=variance, budget=None)


@pytest.mark.parametrize("scale", [1.0, (630 / 500) ** 2])
def test_a_given_window_moves_the_sr_not_the_fov(scale):
    run = _run()
    assert run.averaging_start == 3  # the three unclosed frames
    row = sens._row("p", "v", run, scale=scale, start=1)
    sr = np.exp(-run.residual_variance[1:] * scale)  # from the window given
    assert row["strehl_peak"] == pytest.approx(sr.max(axis=1).mean(), rel=1e-12)
    assert row["strehl_field"] == pytest.approx(sr.mean(), rel=1e-12)
    own = dataclasses.replace(run, residual_variance=run.residual_variance * scale)
    assert row["fov_arcmin"] == pytest.approx(own.corrected_fov_diameter(0.3, start=3),
                                              rel=1e-12)
