"""Leftovers 13-cost (issue 27): the orderings' time before the work, and the kde rule's cost.

References, from outside the code under test: the calls a real ``order_modes`` makes,
counted on ``MutualInformation.score``, on the copy screen of ``information.api`` and on
the gathering of the contributions (the model's terms must count them); Scott's law of
a 2-D kernel's bandwidth, h proportional to n^(-1/6) (Silverman 1986, sec. 4.3), for
the bandwidth of the kde convergence rule's quarters (n / 4 samples: 4^(1/6) times the
whole sample's); the number of bandwidth searches (``scipy.optimize.minimize_scalar``
calls) of one ``mutual_information``. No timing is asserted (benchmarks/RESULTS.md,
"Orderings' cost and the kde rule's quarters, leftovers 13").
"""

import math
import warnings

import numpy as np
import pytest

from modalinfo.information import BiasRuleWarning, MutualInformation, mutual_information
from modalinfo.information import api as mi_api
from modalinfo.information import kde as kde_module
from modalinfo.ordering import order_modes
from modalinfo.ordering import orderings as orderings_module
from modalinfo.ordering.cost import least_ordering_seconds


def _log(n_frames, n_modes, seed=0):
    rng = np.random.default_rng(seed)
    coeffs = rng.standard_normal((n_frames, n_modes)) / np.arange(1, n_modes + 1)
    basis = rng.standard_normal((300, n_modes))
    return coeffs, basis


class _Counts:
    def __init__(self, monkeypatch):
        self.scores = self.screens = self.gathers = self.entries = 0
        score, screen, gather = (MutualInformation.score, mi_api._check_not_a_copy,
                                 orderings_module._contributions)

        def counted_score(est, y):
            self.scores += 1
            return score(est, y)

        def counted_screen(*args, **kw):
            self.screens += 1
            return screen(*args, **kw)

        def counted_gather(a, matrix, frames, pixels):
            self.gathers += 1
            self.entries += a.shape[1] * frames.size
            return gather(a, matrix, frames, pixels)

        monkeypatch.setattr(MutualInformation, "score", counted_score)
        monkeypatch.setattr(mi_api, "_check_not_a_copy", counted_screen)
        monkeypatch.setattr(orderings_module, "_contributions", counted_gather)


@pytest.mark.parametrize("method, n_modes, n_resamples", [
    ("mi_marginal", 6, 3), ("mi_marginal", 2, 1), ("mi_greedy", 6, 2), ("mi_greedy", 9, 0)])
def test_the_models_calls_are_the_scores_an_ordering_makes(monkeypatch, method, n_modes,
                                                           n_resamples):
    # before: mi_marginal was counted 2 M - 2 (it makes 3 M - 2: the scores, the
    # cumulative MI and the swapped rivals) and a replicate 2 M - 3 (it makes 2 M - 2)
    coeffs, basis = _log(40, n_modes)
    counts = _Counts(monkeypatch)
    order_modes(coeffs, basis, method, sample_budget=2000, seed=1, n_resamples=n_resamples,
                block_length=2)
    _, calls = least_ordering_seconds("histogram", 2000, n_modes, n_resamples, 1, method)
    assert calls == counts.scores
    assert counts.screens == counts.scores  # every score runs the copy/curve screens


def test_the_model_has_the_screens_and_the_gathering_the_ordering_does(monkeypatch):
    from modalinfo.ordering.cost import (
        GATHER_SECONDS_PER_ENTRY,
        MI_SECONDS_PER_CALL,
        MI_SECONDS_PER_SAMPLE,
        SCREEN_SECONDS_PER_CALL,
        SCREEN_SECONDS_PER_SAMPLE,
    )

    coeffs, basis = _log(40, 7)
    counts = _Counts(monkeypatch)
    order_modes(coeffs, basis, "mi_marginal", sample_budget=2000, seed=1, n_resamples=4,
                block_length=2)
    n = 2000
    seconds, calls = least_ordering_seconds("histogram", n, 7, 4, 1, "mi_marginal")
    estimates = calls * (MI_SECONDS_PER_CALL["histogram"] + n * MI_SECONDS_PER_SAMPLE[
        "histogram"](n))
    screens = counts.screens * (SCREEN_SECONDS_PER_CALL + n * SCREEN_SECONDS_PER_SAMPLE)
    gathering = counts.entries * GATHER_SECONDS_PER_ENTRY
    assert counts.gathers == 1 + 4  # the ordering's samples and each replicate's
    assert seconds == pytest.approx(estimates + screens + gathering, rel=1e-12)
    assert SCREEN_SECONDS_PER_CALL > MI_SECONDS_PER_CALL["histogram"]  # measured 0.3 ms


class _StopError(Exception):
    pass


def _no_work(monkeypatch):
    # the first work: the contributions of every mode at the samples (1.6 GB and ~10 s
    # at 1000 modes x 2e5 samples), then the estimates
    def stop(*args, **kw):
        raise _StopError("the work started")

    monkeypatch.setattr(orderings_module, "_contributions", stop)
    monkeypatch.setattr(MutualInformation, "fit", stop)


def test_a_thousand_mode_ordering_warns_its_estimate_before_the_work(monkeypatch):
    # 1000 modes x 200 frames x 1000 pixels (2e5 samples, the default budget), histogram,
    # 40 replicates: ~3 min estimated; before, the library ran with no word
    rng = np.random.default_rng(2)
    coeffs = rng.standard_normal((200, 1000))
    basis = rng.standard_normal((1000, 1000))
    _no_work(monkeypatch)
    # round 46 PART a (A03a): the estimate is said to be a lower bound
    with pytest.warns(UserWarning, match=r"1000 modes on 200000 samples .* estimated at "
                                         r"\d+ s of CPU or more \(a lower bound\); use "
                                         r"fewer modes, a smaller `sample_budget`"):
        with pytest.raises(_StopError):
            order_modes(coeffs, basis, "mi_marginal", seed=0)


def test_an_ordering_beyond_max_seconds_is_refused_before_any_estimate(monkeypatch):
    rng = np.random.default_rng(3)
    coeffs, basis = rng.standard_normal((2000, 300)), rng.standard_normal((300, 300))
    _no_work(monkeypatch)
    with pytest.raises(ValueError, match=r"estimator='ksg'.*more than `max_seconds`=3600"):
        order_modes(coeffs, basis, "mi_marginal", estimator="ksg", seed=0)
    with pytest.raises(ValueError, match="more than `max_seconds`=1;"):
        order_modes(coeffs[:, :50], basis[:, :50], "mi_marginal", max_seconds=1, seed=0)
    with pytest.raises(ValueError, match="`max_seconds`"):
        order_modes(coeffs, basis, "mi_marginal", max_seconds=-1.0)
    with pytest.warns(UserWarning, match="estimated at"), pytest.raises(_StopError):
        # no limit: the estimate is said, then the work starts
        order_modes(coeffs, basis, "mi_marginal", estimator="ksg", max_seconds=None,
                    n_resamples=0, seed=0)


def test_the_library_and_the_command_line_share_one_estimate(monkeypatch):
    import argparse

    from modalinfo.cli.cmd_reorder import check_mi_time
    from modalinfo.cli.shared import CommandError
    from modalinfo.ordering import cost

    monkeypatch.setattr(cost, "least_ordering_seconds", lambda *a, **k: (7200.0, 5))
    coeffs, basis = _log(40, 6)
    with pytest.raises(ValueError, match="estimated at 7200 s"):
        order_modes(coeffs, basis, "mi_greedy", n_resamples=0)
    args = argparse.Namespace(estimator="histogram", budget=2000, frame=None,
                              pupil_pixels=16, resamples=0, method="mi_greedy")

    class Log:
        n_frames, n_modes = 40, 6

    with pytest.raises(CommandError, match="2.0 h"):
        check_mi_time(args, Log())


def _zigzag(x, pieces):
    u = x * pieces
    k = np.floor(np.minimum(u, pieces - 1e-12))
    return np.where(k % 2 == 0, u - k, 1 - (u - k))


def test_the_kde_rules_quarters_take_the_whole_samples_bandwidth_by_scotts_law(monkeypatch):
    rng = np.random.default_rng(12)  # an estimate below its xi's Gaussian MI: rule 2 runs
    x = rng.standard_normal(10_000)
    y = 0.6 * x + 0.8 * rng.standard_normal(10_000)
    searches, widths = [], []
    search, resub = kde_module.minimize_scalar, kde_module._Grid2D.resubstitution_mi
    monkeypatch.setattr(kde_module, "minimize_scalar",
                        lambda *a, **k: searches.append(1) or search(*a, **k))
    monkeypatch.setattr(kde_module._Grid2D, "resubstitution_mi",
                        lambda g, h, fx, fy: widths.append((fx.size, h)) or resub(g, h, fx, fy))
    value = mutual_information(x, y, method="kde")
    assert [n for n, _ in widths] == [10_000, 2500, 2500, 2500]  # rule 2 ran
    # before: one bandwidth search per quarter (4 in all)
    assert len(searches) == 1
    for _, h in widths[1:]:  # Scott's law n^(-1/6): n / 4 samples, 4^(1/6) times wider
        assert h == pytest.approx(widths[0][1] * 4 ** (1 / 6), rel=1e-12)
    with warnings.catch_warnings():  # the class road warns too (round 39 PART a)
        warnings.simplefilter("ignore", BiasRuleWarning)
        same = MutualInformation("kde").estimate(x, y)
    assert value == same  # the value is not changed


def test_the_kde_rule_still_warns_a_curve_that_rises_from_the_quarters():
    # three pieces of a zigzag: rule 2 ("rose by") warns on seeds 0-5 before and after
    # (rise 0.065-0.087 nats, allowed 0.05; the quarters' mean moved by <= 0.003 here)
    rng = np.random.default_rng(4)
    x = rng.uniform(0, 1, 5000)
    y = _zigzag(x, 3) + 0.1 * rng.standard_normal(5000)
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        mutual_information(x, y, method="kde")
    said = [str(w.message) for w in record if issubclass(w.category, BiasRuleWarning)]
    assert len(said) == 1 and "rose by" in said[0]
    with warnings.catch_warnings():  # the class road warns too (round 39 PART a)
        warnings.simplefilter("ignore", BiasRuleWarning)
        assert math.isfinite(MutualInformation("kde").estimate(x, y))
