"""The time-varying half of a run: the atmosphere at time ``t``, the DMs' surfaces, the maps.

A :class:`~closedloop.model.LoopModel` holds what a configuration fixes (geometry,
mirrors, sensors, reconstructor); a :class:`LoopState` holds what changes during one run
and composes the parts over it (:mod:`closedloop.parts`): the atmosphere moves
(``evolve_until``), the mirrors take commands (``apply``), and ``forward`` writes every
plane's residual map, turbulence minus the surfaces of the DMs conjugated to it, into
``maps``. The loop (:func:`closedloop.simulate`), its oracle and the error-budget probe
(:class:`closedloop.budget.BudgetProbe`) all drive the run through these methods.
"""

from __future__ import annotations

import numpy as np

from closedloop.optics import _kernels
from closedloop.optics.atmosphere import Atmosphere

__all__ = ["LoopState"]


class LoopState:
    """One run's atmosphere, mirror surfaces and plane maps.

    Parameters
    ----------
    model : LoopModel
        The configuration's static parts.
    atmosphere : Atmosphere
        The run's layers (:meth:`closedloop.model.LoopModel.atmosphere`), on the planes'
        grids.
    maps : list of (n_p, n_p) ndarray or None
        Where :meth:`forward` writes the residual maps, one writeable C-contiguous float64
        array per plane (e.g. ``model.science.plane_views()``, so that the science camera
        reads them); None: new arrays.

    Attributes
    ----------
    maps : list of (n_p, n_p) ndarray
        The residual maps [rad at ``r0_wavelength``] after the last :meth:`forward`.
    surfaces : list of (n_disc,) ndarray
        Each DM's surface [rad] on its disc's pixels (flat after :meth:`reset`).
    """

    def __init__(self, model, atmosphere: Atmosphere, maps: list[np.ndarray] | None = None):
        self.model = model
        self.atmosphere = atmosphere
        if maps is None:
            maps = [np.zeros((p.n, p.n)) for p in model.geometry.planes]
        self.maps = maps
        self.surfaces = [np.zeros(dm.pixels.size) for dm in model.dms]
        # a plane holding several layers sums them through one work array per plane
        self._work = {p: np.empty((plane.n, plane.n))
                      for p, plane in enumerate(model.geometry.planes) if len(plane.layers) > 1}

    @property
    def t(self) -> float:
        """Current time [s] (the atmosphere's)."""
        return self.atmosphere.t

    def reset(self) -> None:
        """Move the atmosphere back to ``t = 0`` and flatten the mirrors."""
        self.atmosphere.reset()
        for s in self.surfaces:
            s[:] = 0.0

    def evolve_until(self, t: float) -> None:
        """Move the atmosphere to time ``t`` [s] (frozen flow)."""
        self.atmosphere.evolve_until(t)

    def apply(self, command: np.ndarray) -> None:
        """Put ``command`` ``(n_modes,)`` (every DM's, DM 0 first) on the mirrors."""
        model = self.model
        for d, dm in enumerate(model.dms):
            self.surfaces[d] = dm.forward(command[model.mode_slices[d]])

    def turbulence(self, out: list[np.ndarray]) -> list[np.ndarray]:
        """Write every plane's turbulent phase [rad] at the current time into ``out``.

        ``out``: one writeable C-contiguous float64 ``(n_p, n_p)`` array per plane (not
        checked: the hot loop). Returns ``out``.
        """
        atm = self.atmosphere
        for p, plane in enumerate(self.model.geometry.planes):
            if plane.layers:
                atm.forward(out[p], plane.layers, self._work.get(p))
            else:
                out[p][:] = 0.0
        return out

    def forward(self) -> list[np.ndarray]:
        """Write every plane's residual (turbulence minus its DMs) into :attr:`maps`."""
        maps = self.turbulence(self.maps)
        for p, plane in enumerate(self.model.geometry.planes):
            for d in plane.dms:
                dm = self.model.dms[d]
                _kernels.subtract_scatter(maps[p], dm.pixels, self.surfaces[d], 1.0)
        return maps
