"""assess_quality leaves the process's warning state alone (round 9, t-thr-quality-*).

Reference: Python's documented rule that ``warnings.catch_warnings`` swaps the global
filter list and is not thread-safe. ``assess_quality`` silenced numpy's "All-NaN slice"
RuntimeWarning that way: a thread running it made another thread's BiasRuleWarning vanish
(4 in 40 calls) and could leave "ignore RuntimeWarning" installed for good. Now it must
never enter ``catch_warnings`` (checked by replacing it with a function that fails), must
still emit no warning on an all-NaN column (filters set to "error"), and its report must
match the robust statistics computed by numpy on the same columns.
"""

import warnings

import numpy as np

from modalinfo.telemetry import assess_quality


def test_no_catch_warnings_and_no_warning_on_an_all_nan_column(monkeypatch):
    rng = np.random.default_rng(0)
    x = rng.standard_normal((2000, 3))
    x[:, 1] = np.nan
    x[700, 2] = 80.0

    class Refuse(warnings.catch_warnings):  # a class: numpy.testing subclasses it
        def __enter__(self):
            raise AssertionError("assess_quality entered warnings.catch_warnings")

    assess_quality(x[:, [0]])  # numba loads its kernels (which enters catch_warnings) first
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with monkeypatch.context() as patch:
            patch.setattr(warnings, "catch_warnings", Refuse)
            report = assess_quality(x)
    assert 700 in report.flagged_frames
    assert np.isnan(report.median[1])
    for j in (0, 2):
        med = np.median(x[:, j])
        assert report.median[j] == med
        # 1 / Phi^-1(3/4) = 1.482602218505602 (the normal consistency constant of the MAD)
        assert np.isclose(report.sigma[j], 1.482602218505602 * np.median(np.abs(x[:, j] - med)),
                          rtol=1e-12)
