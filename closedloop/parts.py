"""The protocol every part of the loop shares (hcipy's ``reset`` / ``evolve_until`` / ``forward``).

A part of the loop is one of: the atmosphere, a deformable mirror, a wavefront sensor,
the science camera, the controller. Each has ``reset()`` (back to the state right after
construction); a part in which time matters also has the ``t`` property and
``evolve_until(t)``; an optical part has ``forward(...)``, its step from what it
receives to what it gives (the atmosphere: its phase on a plane; a DM: its surface from
a command; a WFS: its measurements from the plane maps; the science camera: the
residual variance in each direction). The controller's step is
:meth:`closedloop.control.controller.Controller.step` (a command from a modal residual).
:class:`closedloop.state.LoopState` composes them over one run, and
:func:`closedloop.simulate` is the loop over a :class:`~closedloop.state.LoopState`.

A new kind of wavefront sensor is one class implementing :class:`Sensor` (usually a
subclass of :class:`closedloop.optics.wfs.WavefrontSensor`, which supplies the sparse
measurement path and the reconstructor), the ``build`` of a
:class:`closedloop.kinds.SensorKind` registered under its config ``kind`` with
:func:`closedloop.kinds.register_sensor_kind` (docs/ARCHITECTURE.md, "To add a sensor
kind / a DM kind").
"""

from __future__ import annotations

from typing import ClassVar, Protocol, runtime_checkable

import numpy as np

__all__ = ["Part", "TimedPart", "Sensor"]


@runtime_checkable
class Part(Protocol):
    """Anything the loop holds: it can go back to its initial state."""

    def reset(self) -> None:
        """Go back to the state right after construction."""


@runtime_checkable
class TimedPart(Part, Protocol):
    """A part that has a clock (the atmosphere, the loop state)."""

    @property
    def t(self) -> float:
        """Current time [s]."""

    def evolve_until(self, t: float) -> None:
        """Advance (or move: frozen flow is stateless) to time ``t`` [s]."""


@runtime_checkable
class Sensor(Part, Protocol):
    """A wavefront sensor: plane maps in, measurements out.

    Attributes
    ----------
    kind : str
        The config's ``wfss[j].kind`` it implements (the registry key).
    index : int
        Which WFS of the configuration.
    n_measurements : int
        Length of one measurement vector.
    noise_rms : float or (n_measurements,) ndarray
        Per-measurement noise RMS [measurement units] (0: noise-free); an array when the
        measurements differ in noise.
    reconstructor : (M, n_measurements) ndarray or None
        Measurements to the modal residual of its DM (None: the identity).
    """

    kind: ClassVar[str]
    index: int
    n_measurements: int
    noise_rms: float | np.ndarray
    reconstructor: np.ndarray | None

    def forward(self, plane_maps: list[np.ndarray],
                noise: np.ndarray | None = None) -> np.ndarray:
        """Measurements ``(n_measurements,)`` from the residual maps of every plane."""

    def interaction_with(self, dm) -> np.ndarray:
        """Measurements of a unit command of each mode of ``dm``, ``(n_measurements, M)``."""

    def model_error_variance(self, r0s: list[float], model_error: float) -> float | np.ndarray:
        """Extra variance per measurement (float or array) the MAP reconstructor assumes."""
