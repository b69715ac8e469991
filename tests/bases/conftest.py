"""Helpers shared by the basis tests (reference: the laws written out here, not the code).

- :func:`dense_influence`: the influence functions written out pixel by pixel,
  ``coupling ** (r**2 / pitch**2)`` on each actuator's square support (test_influence,
  test_influence_state_audit10).

Test files import the functions (``from .conftest import dense_influence``).
"""

import numpy as np


def dense_influence(f) -> np.ndarray:
    """The influence functions of ``f`` written out pixel by pixel: ``(n_pupil, n_valid)``."""
    mask = f.pupil.mask
    x, y = f.pupil.x[mask], f.pupil.y[mask]
    out = np.zeros((x.size, f.n_valid))
    for k, (xa, ya) in enumerate(f.valid_positions):
        u, v = x - xa, y - ya
        value = f.coupling ** ((u ** 2 + v ** 2) / f.pitch ** 2)
        out[:, k] = np.where((np.abs(u) <= f.radius) & (np.abs(v) <= f.radius), value, 0.0)
    return out
