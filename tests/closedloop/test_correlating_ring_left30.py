"""The correlating SH's ring subapertures at altitude and its budget's noise term (left30-solar).

Issue 27 (docs/CLOSEDLOOP.md, "Correlating SH noise weights and ring subapertures";
docs/ADVERSARIAL.md, "Leftovers 30-solar"). References (outside the code under test):

- the law of a layer at the DM's altitude, corrected uniformly over a field the DM's disc
  holds: the ideal sensor's worst / best SR 0.96-0.98 and the geometric SH's 0.95-0.97
  on this single-layer case (tests/closedloop/test_field_conjugated_dm_left27.py,
  docs/ADVERSARIAL.md "Leftovers 28-field"). With the valid rule and the directions'
  use on the margined light (left29-corr) the correlating SH kept 180 of the 200
  subapertures the beam half-lights and seed 1's corner fell to 0.74 of the best;
- a Monte Carlo of the loop itself: two runs with the same turbulence (seed), the
  measurement noise on and off; the loop is linear, so the difference of the two runs'
  commands is the noise propagated through the reconstructor and the servo, and its
  variance seen in the science directions (the budget's own projection of a command
  vector, ``BudgetProbe._variance``) is what the budget's noise term predicts, with no
  cross term with the residual. The sub-pixel factor of the slopes' noise (1.4-1.5 on
  the ground WFS's closed loop) is what the budget missed before: MC / budget 1.44
  with the whole-pixel law, 1.02 with the applied factor (60 frames, seed 0).
"""

import dataclasses as dc

import numpy as np

from closedloop import presets, simulate
from closedloop.budget import BudgetProbe
from closedloop.model import LoopModel

from .test_correlating_field_rule_left29 import _config


def test_single_layer_is_corrected_over_the_field_like_the_ideal_sensor():
    """Worst / best SR over the 12" field >= 0.9 (seed 1, 0.3 s).

    Measured: 0.953 / 0.975 / 0.963 / 0.953 on seeds 0-3 (left29-corr's valid set:
    0.955 / 0.740 / 0.864 / 0.937). The ideal sensor's 0.96-0.98 is the law; 0.9 leaves
    the spread of seeds 0-3 below it and seed 1's 0.74 of before far outside.
    """
    run = simulate(_config(), 0.3, seed=1, progress=False)
    sr = np.asarray(run.strehl_map())
    assert sr.max() > 0.5, f"the loop did not correct the layer: {np.round(sr, 3)}"
    assert sr.min() >= 0.9 * sr.max(), f"field not corrected uniformly: {np.round(sr, 3)}"


def test_budget_noise_term_is_the_loops_propagated_noise():
    """The budget's noise term against the noise the loop propagates (noise on - off).

    table1-solar at 40 e- per pixel (0.012 px rms per slope, the linear regime), noise on
    the ground WFS's relative slopes only (the trackers' noise, whose factor is ~1,
    dominates the tip-tilt otherwise and hides the slopes'). 40 frames, seed 0. The
    Monte Carlo's standard error over the frames is ~3 % (correlated frames), the
    budget's 64 draws add a few %; the bound 0.15 is ~2.5 times their combined error,
    far from before's 1.44 (the whole-pixel law, the factor 1.45 the loop's shifts
    applied left out).
    """
    c = presets.get("table1-solar")
    c = dc.replace(c, wfss=tuple(dc.replace(w, signal=40.0) for w in c.wfss))
    m = LoopModel(c)
    for w in m.wfss:
        w.noise_rms = np.asarray(w.noise_rms).copy()
        w.noise_rms[-2:] = 0.0
        if w.index > 0:
            w.noise_rms[:] = 0.0
    duration = 40 * c.loop.time_step
    on = simulate(c, duration, seed=0, progress=False, model=m, budget_every=1)
    b = on.budget
    measure = LoopModel.measure
    m.measure = lambda maps, rng: measure(m, maps, None)
    off = simulate(c, duration, seed=0, progress=False, model=m)

    def commands(run):
        return np.concatenate([run.logs[f"dm{i}.commands"].coeffs
                               for i in range(len(m.dms))], axis=1)

    delta = commands(on) - commands(off)
    probe = BudgetProbe(m, None, 1)
    scale = (c.r0_wavelength / c.wavelength) ** 2
    mc = np.mean([probe._variance(None, delta[k]) for k in b.frames], axis=0) * scale
    ratio = mc.mean() / b.noise.mean()
    assert abs(ratio - 1.0) < 0.15, f"Monte Carlo / budget noise = {ratio:.3f}"
