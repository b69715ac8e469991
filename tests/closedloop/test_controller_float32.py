"""The controller's ``(M, M)`` products of a 4-m loop in float32 (``float32_from``).

Reference (outside the code): numpy's float64 product ``m + R G seen`` (the POL of
pseudo-open-loop control), with the standard worst-case bound of a dot product of ``n``
terms whose matrix entries are rounded to float32 (Higham, *Accuracy and Stability of
Numerical Algorithms*, 2nd ed., eq. 3.5): ``(n + 2) u |R G| |seen|``, ``u = 2^-24``, plus
the float64 addition of ``m``. By default (``float32_from = inf``, every loop without an
actuator mirror) the controller keeps numpy's float64 bits.
"""

import numpy as np

from closedloop.control.controller import Controller

U64 = 2.0 ** -53
U32 = 2.0 ** -24


def test_the_controllers_products_in_float32_only_when_asked():
    rng = np.random.default_rng(3)
    n = 40
    rg = rng.standard_normal((n, n))
    kw = dict(gain=0.5, leak=0.0, delay_frames=0.5, integration_frames=1.0)
    m = rng.standard_normal(n)
    plain, single = Controller(n, sensed=rg, **kw), Controller(n, sensed=rg, float32_from=0.0,
                                                                **kw)
    first = rng.standard_normal(n)
    for c in (plain, single):
        c.step(first)  # a first command, so that the mirror has moved
    seen = plain.seen_commands()
    np.testing.assert_array_equal(seen, single.seen_commands())
    # reference: the POL of pseudo-open-loop control, m + R G seen (float64, numpy)
    _, pol, _ = plain.step(m)
    assert np.array_equal(pol, m + rg @ seen)
    _, pol32, _ = single.step(m)
    bound = (n + 2) * U32 * (np.abs(rg) @ np.abs(seen)) + 4 * U64 * np.abs(m + rg @ seen)
    assert np.all(np.abs(pol32 - (m + rg @ seen)) <= bound)
    assert not np.array_equal(pol32, pol)
