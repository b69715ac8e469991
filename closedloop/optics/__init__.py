"""What the light meets: atmosphere, planes and footprints, DMs, WFSs, the science camera.

Each part follows the protocol of :mod:`closedloop.parts` (``reset``, ``evolve_until``,
``forward``); numba kernels sit beside their wrappers (``_kernels``,
``_atmosphere_kernels``, ``_shift_kernels``). The solar correlating Shack-Hartmann:
the scene (``granulation``), shift measurement (``shifts``), standalone image formation
(``correlating``, with ``photon_budget`` and ``image_sampling``) and the loop's sensor
kind ``"correlating"`` (``correlating_sensor``).

The built-in sensor and mirror kinds register themselves with :mod:`closedloop.kinds`
when their modules are imported; the import below is the one place that lists them (a
new kind's module is added to it).
"""

from closedloop.optics import (  # noqa: F401  (register the kinds)
    actuator_dm,
    correlating_sensor,
    dm,
    wfs,
)
