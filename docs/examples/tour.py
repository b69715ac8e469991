"""A tour of the library in Python (the README's tour; run from the repository root).

Run: ``python docs/examples/tour.py``. It reads the shipped closed-loop log, orders
its modes by MI, draws a fitting-error curve, estimates MI with intervals and
evaluates two predictors.
"""

import numpy as np

import modalinfo.io
from modalinfo.bases import KLBasis, Pupil, ZernikeBasis, noll_residual_variance
from modalinfo.forecast import ARMAPredictor, PersistencePredictor, evaluate
from modalinfo.information import mutual_information, mutual_information_ci
from modalinfo.ordering import fitting_error, order_modes

log = modalinfo.io.load("data/kaos_like_closed_loop.npz")  # ModalLog, (8000, 27) Z2..Z28 in rad
pupil = Pupil(64, diameter=0.7)
zb = ZernikeBasis(pupil, modes=log.modes)  # unit-RMS Noll Zernikes, labels "Z2".."Z28"
kl = KLBasis.from_turbulence(pupil, 27)  # Kolmogorov K-L (Dai 1995)

print(noll_residual_variance(21))  # Delta_21 = 0.0208 (D/r0)^(5/3) rad^2

greedy = order_modes(log, zb, method="mi_greedy", estimator="histogram", seed=0)
print(greedy.labels[:7], greedy.gain[:7])  # modes adding most MI, with gains
curve = fitting_error(log, zb, greedy.order, units="waves2")
print(curve.modes_to_reach(1e-4))

x, y = np.random.default_rng(0).multivariate_normal([0, 0], [[1, 0.6], [0.6, 1]], 10_000).T
print(mutual_information(x, y, method="kde"))  # ~ -0.5 ln(1 - 0.36) = 0.223 nats
print(mutual_information_ci(x, y, seed=0))  # moving-block bootstrap interval
print(mutual_information(np.round(x, 1), np.round(y, 1), method="ksg"))  # ties: seeded noise

arma = ARMAPredictor(order=(2, 3), horizon=10).fit(log.coeffs[:7000])
arma.reset()
for frame in log.coeffs[7000:7010]:
    forecast = arma.update(frame)  # (10, 27): O(1) per loop step
result = evaluate({"persistence": PersistencePredictor(), "arma": ARMAPredictor()}, log, train=7000)
print(result.table())
