"""The error budget's noise term takes the correlating SH's factor over the budget's frames.

docs/MUTATION.md, "Planted bugs, round 23", R23-N2: left30-solar's budget scales each
correlating SH's ``noise_rms ** 2`` by the mean variance factor ``forward`` applied over
the budget's frames (from the averaging start on). Its Monte Carlo test kept nearly all
of a 40-frame run, so a budget averaging the factor over every frame since the sensor
was built (the loop's closing included, where the shifts and so the factor are larger:
1.9-2.3 open, 1.06-1.5 closed on table1-solar) passed within its 15 % bound.

Reference (outside the code): the law of the budget's noise term, a covariance
``R N R^T`` linear in ``N`` (drawn as ``sqrt(N) n`` with the same seeded ``n``): with
a per-frame factor of 5 before the averaging start and 2 from it on (the cumulative
sums the sensor keeps, built here with numpy), the noise term is exactly twice that of
unit factors; a window reaching back into the first frames reads 3.5 times.
"""

import numpy as np

from closedloop import presets
from closedloop.budget import BudgetProbe
from closedloop.model import LoopModel


def test_the_noise_factor_is_averaged_from_the_averaging_start_on():
    m = LoopModel(presets.get("table1-solar"))
    n_dir = len(m.science.directions)
    n_frames, start = 10, 5
    per_frame = np.where(np.arange(n_frames) < start, 5.0, 2.0)
    cumulative = np.cumsum(per_frame)

    def probe(factors: bool) -> BudgetProbe:
        p = BudgetProbe(m, None, 1)
        for k in range(n_frames):
            p.rows["frame"].append(k)
            for key in ("fitting", "sh", "temporal"):
                p.rows[key].append(np.zeros(n_dir))
            p.noise_factors.append([
                (np.full(w.n_measurements, cumulative[k]), k + 1) if factors else None
                for w in m.wfss])
        return p

    measured = np.zeros((n_frames, n_dir))
    unit = probe(False).result(measured, start, 1.0, seed=3).noise
    assert np.all(unit > 0.0)
    noise = probe(True).result(measured, start, 1.0, seed=3).noise
    np.testing.assert_allclose(noise, 2.0 * unit, rtol=1e-9)
