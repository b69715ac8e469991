"""Control: the POL integrator with its predictor hook, and the predictor-in-the-loop type.

``controller.Controller`` forms the pseudo-open-loop (POL) coefficients and the command;
``predictors.LoopPredictor`` is what a run forecasts with (a name, a
``modalinfo.forecast`` predictor and how it is trained; ``ORACLE`` the true future).
"""
