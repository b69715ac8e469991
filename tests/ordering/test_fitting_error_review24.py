"""Planted-bug review 24 (issue 27): the Parseval difference in waves^2, the PCA
refusal's pair names and the JSON's ``noise_assessed``.

References (outside the code): the Parseval sum of the dropped K-L coefficients'
squares formed with numpy (in rad^2, and in waves^2 by ``(1 / 2 pi)^2``: a relative
difference does not depend on the unit); ``numpy.corrcoef`` of the correlated pair,
whose columns are named by hand; the definition of ``noise_assessed`` (bootstrap
bounds of the margins present).
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest

from modalinfo.bases import KLBasis, Pupil
from modalinfo.ordering import fitting_error, order_modes
from modalinfo.ordering.fitting_error import PupilSamplingWarning
from modalinfo.telemetry import ModalLog

MODES = np.arange(2, 12)


def test_parseval_difference_is_the_same_in_waves2():
    rng = np.random.default_rng(24)
    a = rng.standard_normal((2000, MODES.size)) / np.arange(1, MODES.size + 1)
    log = ModalLog(a, modes=MODES, units="rad", rate=1000.0, wavelength=5e-7)
    kb = KLBasis.from_turbulence(Pupil(24), MODES.size, zernike_modes=MODES)
    with pytest.warns(PupilSamplingWarning):
        rad = fitting_error(log, kb, units="rad2")
    with pytest.warns(PupilSamplingWarning) as rec:
        waves = fitting_error(log, kb, units="waves2")
    akl = a @ np.asarray(kb.zernike_from_kl)
    par = np.cumsum(np.mean(akl**2, axis=0)[::-1])[::-1] / (2 * np.pi) ** 2  # waves^2
    got = waves.curve(include_zero=True)[:-1]
    rel = (got - par) / par
    worst = rel[np.argmax(np.abs(rel))]
    assert abs(worst) > 0.01
    assert waves.parseval_difference == pytest.approx(worst, rel=1e-9)
    assert waves.parseval_difference == pytest.approx(rad.parseval_difference, rel=1e-9)
    assert rec[0].message.difference == pytest.approx(worst, rel=1e-9)


def test_pca_refusal_names_the_pair_after_an_empty_mode():
    rng = np.random.default_rng(10)
    b = rng.standard_normal((4000, 4)) @ rng.standard_normal((4, 4))
    b = b - b.mean(axis=0)
    _, _, vt = np.linalg.svd(b, full_matrices=False)
    b = b @ vt.T
    c, s = np.cos(1e-3), np.sin(1e-3)
    b[:, [1, 3]] = b[:, [1, 3]] @ np.array([[c, -s], [s, c]])
    r = abs(np.corrcoef(b[:, 1], b[:, 3])[0, 1])
    b = np.column_stack([np.zeros(4000), b])  # an empty first mode: the pair is mode3, mode5
    q, _ = np.linalg.qr(rng.standard_normal((64, 5)))
    with pytest.raises(ValueError, match=r"modes mode3 and mode5 have \|correlation\| "
                       + re.escape(f"{r:.3g}")):
        order_modes(b, q * 8.0, "pca")


def test_noise_assessed_follows_the_margins_not_the_replicate_count():
    rng = np.random.default_rng(2)
    a = rng.standard_normal((400, 3)) * [1.0, 0.7, 0.3]
    q, _ = np.linalg.qr(rng.standard_normal((64, 3)))
    res = order_modes(a, q * 8.0, "mi_greedy", sample_budget=5000, seed=0, n_resamples=40)
    assert res.margin_low is not None and res.to_dict()["noise_assessed"] is True
    bare = dataclasses.replace(res, margin_low=None)  # e.g. a hand-made result
    assert bare.n_resamples == 40
    assert bare.to_dict()["noise_assessed"] is False
