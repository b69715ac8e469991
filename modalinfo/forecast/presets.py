"""Named predictor configurations shared by the command line and the paper figures.

One place defines what ``modalinfo forecast --predictors arma,nn`` and Figure 5 mean by
"ARMA" or "the paper's neural net", so the two cannot drift apart.
"""

from __future__ import annotations

from collections.abc import Callable

from modalinfo.forecast.arma import ARMAPredictor
from modalinfo.forecast.base import Predictor
from modalinfo.forecast.info import InfoPredictor
from modalinfo.forecast.info_nn import InfoNNPredictor
from modalinfo.forecast.linear import LinearPredictor
from modalinfo.forecast.multivariate import MultivariatePredictor, RLSMultivariatePredictor
from modalinfo.forecast.nn import NeuralNetPredictor

__all__ = ["PRESETS", "make_predictor"]

#: short name -> (label used in tables and figures, factory of a fresh unfitted predictor)
PRESETS: dict[str, tuple[str, Callable[[], Predictor]]] = {
    "linear": ("linear (a=2, b=-1)", lambda: LinearPredictor()),
    "linear-ls": ("linear (LS a, b)", lambda: LinearPredictor(fit_weights=True)),
    "arma": ("ARMA(2,3)", lambda: ARMAPredictor(order=(2, 3))),
    "arma-aic": ("ARMA (AIC)", lambda: ARMAPredictor(order="aic")),
    "nn": ("NN 10-10-1, 2000 patterns", lambda: NeuralNetPredictor()),
    "nn-paper": ("NN paper (10 patterns)", lambda: NeuralNetPredictor.paper()),
    "multivariate": ("multivariate VAR(4)", lambda: MultivariatePredictor(order=4, alpha="gcv")),
    "rls": ("multivariate RLS", lambda: RLSMultivariatePredictor(order=4)),
    "info": ("info (CMI-selected sparse LS)", lambda: InfoPredictor()),
    "info-nn": ("info-nn (info + random tanh features)", lambda: InfoNNPredictor()),
}


def make_predictor(name: str) -> Predictor:
    """Return a fresh, unfitted predictor for a preset name.

    Parameters
    ----------
    name : str
        One of the keys of :data:`PRESETS`.

    Returns
    -------
    Predictor
        A new instance (never shared between calls).

    Raises
    ------
    ValueError
        If ``name`` is not a preset.
    """
    if name not in PRESETS:
        raise ValueError(f"`name` must be one of {', '.join(PRESETS)}; got {name!r}.")
    return PRESETS[name][1]()
