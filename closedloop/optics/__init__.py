"""What the light meets: atmosphere, planes and footprints, DMs, WFSs, the science camera.

Each part follows the protocol of :mod:`closedloop.parts` (``reset``, ``evolve_until``,
``forward``); numba kernels sit beside their wrappers (``_kernels``,
``_atmosphere_kernels``, ``_shift_kernels``). The solar correlating Shack-Hartmann:
the scene (``granulation``), shift measurement (``shifts``), standalone image formation
(``correlating``) and the loop's sensor kind ``"correlating"`` (``correlating_sensor``).
"""
