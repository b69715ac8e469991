"""The remedies that the cost and sampling notes give must apply to the run (round 53 PART b).

Reference: the arguments of the run itself. A note after ``--estimator histogram`` named
the histogram as the faster estimator to use (W43); the fitting-error note after 100
pixels called 64 pixels larger (W16 / W18). The Gram eigenvalues are numpy's
(``eigvalsh`` of the sampled basis' Gram matrix), far from 1 for Z2..Z1001 on 100
pixels (1.03e-05-2.51).
"""

from __future__ import annotations

import argparse

import numpy as np

from modalinfo.cli.cmd_fitting_error import _sampling_note
from modalinfo.cli.cmd_reorder import _shorten
from modalinfo.telemetry import ModalLog


def test_faster_estimators_are_faster_than_the_one_in_use():
    for estimator, named in (("ksg", "(histogram, gaussian)"), ("kde", "(histogram, gaussian)"),
                             ("histogram", "(gaussian)")):
        args = argparse.Namespace(estimator=estimator, resamples=40, stability=None)
        assert _shorten(args).endswith(f"a faster --estimator {named}"), _shorten(args)
    args = argparse.Namespace(estimator="gaussian", resamples=40, stability=None)
    assert "faster" not in _shorten(args)


def test_sampling_note_names_no_smaller_pupil():
    log = ModalLog(np.random.default_rng(0).standard_normal((50, 1000)), rate=1000.0,
                   modes=list(range(2, 1002)))
    args = argparse.Namespace(pupil_pixels=100, command="fitting-error")
    assert _sampling_note(args, log)
    err = "\n".join(args._notes)
    assert "not orthonormal" in err
    assert "(64: within 7 %)" not in err  # 64 is not larger than 100
    assert "more --pupil-pixels than 100" in err
