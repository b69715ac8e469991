"""closedloop: a numba-accelerated layer-oriented MCAO simulator of a 4 m solar telescope.

The simulator of the paper's Section 3.4 (LOST simulations, Table 1, Figures 2-4). It
composes the parts of ``modalinfo`` (Zernike bases, the servo model, ``ModalLog``, the
forecast predictors used online) and returns residual wavefronts and telemetry that the
analysis library reads unchanged. ``modalinfo`` never imports closedloop.

Public surface::

    from closedloop import presets, simulate, SimulationConfig, SimulationResult
    config = presets.get("table1")
    result = simulate(config, 1.0, predictor=None, seed=0)
    result = run_trained(config, "arma-aic", 1.0, seed=0)   # train on the no-prediction run
    result.strehl_peak, result.strehl_map(), result.corrected_fov_diameter(0.3)
    result.logs["dm0.pol"]          # a modalinfo.telemetry.ModalLog
    result.save("run.h5"); SimulationResult.load("run.h5")

Rooms (see docs/ARCHITECTURE.md):

- ``closedloop.optics``: what light meets, each a part of the loop's protocol
  (``parts.py``): ``atmosphere`` / ``phase_screen`` (frozen flow), ``geometry`` (planes,
  footprints), ``dm``, ``wfs`` (MFoV layer-oriented Shack-Hartmann and the ideal sensor,
  through a registry), ``science`` (Strehl over the field), their numba kernels, and the
  solar sensor in progress (``granulation``, ``shifts``, ``correlating``; issue 20);
- ``closedloop.control``: ``controller`` (POL integrator and predictor hook) and
  ``predictors`` (:class:`LoopPredictor`, :data:`ORACLE`);
- the loop itself, top level: ``config`` (frozen dataclasses, TOML/JSON), ``presets``,
  ``model`` (:class:`LoopModel`), ``state`` (``LoopState``), ``simulation`` (the loop),
  ``budget`` (error-budget probe), ``result``, ``training`` (:func:`run_trained`),
  ``resources``, ``theory``, ``aot`` (export as an AO Telemetry system:
  ``aot.export_aot(result, path)``);
- ``closedloop.studies``: studies made of runs (``compression``: Figure 6;
  ``sensitivity``);
- the command line apart: ``cli``, ``sweep`` (grids of runs on ``modalinfo.batch``).
"""

import importlib

#: public name -> the module that defines it. Imported on first use (PEP 562), not here:
#: ``python -m closedloop`` imports this package before its ``__main__`` can install the
#: Ctrl-C handler, so an eager import of NumPy/SciPy/numba here ran seconds of work
#: outside any handler (a KeyboardInterrupt traceback, issue 27 round 3, x06).
_LAZY = {
    "presets": "closedloop.presets",
    "simulate": "closedloop.simulation",
    "LoopModel": "closedloop.simulation",
    "run_trained": "closedloop.training",
    "LoopPredictor": "closedloop.control.predictors",
    "ORACLE": "closedloop.control.predictors",
    "SimulationConfig": "closedloop.config",
    "load_config": "closedloop.config",
    "save_config": "closedloop.config",
    "SimulationResult": "closedloop.result",
}


def __getattr__(name: str):
    """Import a public name on first use (PEP 562); a submodule is itself."""
    try:
        module = importlib.import_module(_LAZY[name])
    except KeyError:
        raise AttributeError(f"module 'closedloop' has no attribute {name!r}") from None
    value = module if module.__name__ == f"closedloop.{name}" else getattr(module, name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "presets",
    "simulate",
    "run_trained",
    "LoopModel",
    "LoopPredictor",
    "ORACLE",
    "SimulationConfig",
    "SimulationResult",
    "load_config",
    "save_config",
]
