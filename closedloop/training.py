"""Train a predictor on a reference run, then run the loop with it: :func:`run_trained`.

The one place the paper's recipe is written (the command line's ``run`` and ``compare``,
sweeps, the figures' runs and the compression study all call it): a predictor that
needs training is fitted on the POL of the no-prediction run of the same config and
duration (the same atmosphere unless ``train_seed`` names another), after its loop
closure and after 15 ms (:meth:`closedloop.control.predictors.LoopPredictor.trained`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from closedloop.config import SimulationConfig
from closedloop.control.predictors import LoopPredictor
from closedloop.result import SimulationResult
from closedloop.simulation import LoopModel, simulate

__all__ = ["run_trained"]


def run_trained(config: SimulationConfig, predictor: str | LoopPredictor, duration: float, *,
                seed: int | None = None, train_seed: int | None = None,
                reference: SimulationResult | None = None, model: LoopModel | None = None,
                progress: bool | None = None, budget_every: int | None = None,
                memory_limit: float | None = None,
                control_basis: np.ndarray | None = None) -> SimulationResult:
    """Train ``predictor`` on a no-prediction run if it needs it, then simulate with it.

    Parameters
    ----------
    config : SimulationConfig
    predictor : str or LoopPredictor
        A name of ``closedloop.control.predictors.NAMES`` (checked here, once) or a
        :class:`LoopPredictor` (trained already or not).
    duration : float
        Simulated time of the run and of the reference run [s].
    seed : int or None
        The run's atmosphere and noise; None: ``config.seed``.
    train_seed : int or None
        Seed of the reference run the predictor trains on; None: ``seed`` (the same
        atmosphere, as in the paper).
    reference : SimulationResult or None
        The no-prediction run to train on, if already made (same config and duration;
        its seed is taken as ``train_seed``'s when that is given and differs, else it is
        used as is).
    model : LoopModel or None
        Set-up shared by the reference run and the run.
    progress : bool or None
        tqdm bars of the loops (``simulate``'s).
    budget_every, memory_limit, control_basis
        Passed to :func:`closedloop.simulate` for the run (``memory_limit`` also for the
        reference run). With ``control_basis`` the predictor is fitted on the projected
        POL ``POL @ B`` (what the loop feeds it).

    Returns
    -------
    SimulationResult
        Its ``predictor`` is the name given (``"arma-aic"``); for a predictor trained
        here, ``provenance["train_seed"]`` is the seed of the run it was fitted on.

    Raises
    ------
    ValueError
        An unknown name, or a reference run too short to train on.
    """
    spec = predictor if isinstance(predictor, LoopPredictor) else LoopPredictor.from_name(predictor)
    model = model or LoopModel(config)
    seed = config.seed if seed is None else seed
    fitted_here = spec.needs_training
    if fitted_here:
        if reference is None or (train_seed is not None and train_seed != seed):
            reference = simulate(config, duration, seed=seed if train_seed is None else train_seed,
                                 model=model, progress=progress, memory_limit=memory_limit)
        spec = spec.trained(reference, basis=control_basis)
    result = simulate(config, duration, predictor=spec, seed=seed, model=model,
                      progress=progress, budget_every=budget_every, memory_limit=memory_limit,
                      control_basis=control_basis)
    if fitted_here and getattr(result, "provenance", None) is not None:
        # the atmosphere the predictor was fitted on: `--train-seed 3` was kept only in
        # the command line, and a Python run's record had no trace of it (round 39 PART b,
        # C17 / C18)
        record = {**result.provenance, "train_seed": int(reference.seed)}
        result = dataclasses.replace(result, provenance=record)
    return result
