"""The KDE entropy of a vibration line's amplitude law says it is biased (round 41 PART a V16).

Reference: ``A sin(phi)`` with ``phi`` uniform has the arcsine law on [-A, A], whose
differential entropy is ``ln(pi A / 2)`` (closed form). ``entropy(method='kde')`` gave
0.72 nats for A = 1 (exact 0.452) at n = 2e4 without a word; the KDE's error is far
beyond its sampling error (sd < 0.01 here: three seeds gave 0.721-0.724).
"""

import math
import warnings

import numpy as np
import pytest

from modalinfo.information import BiasRuleWarning, entropy


def _arcsine(n, seed):
    return np.sin(np.random.default_rng(seed).uniform(0.0, 2.0 * math.pi, n))


def test_kde_entropy_of_a_line_warns():
    x = _arcsine(20_000, 0)
    with pytest.warns(BiasRuleWarning, match="Kozachenko-Leonenko"):
        value = entropy(x, method="kde")
    assert value - math.log(math.pi / 2) > 0.2  # the bias the warning names


def test_ksg_entropy_of_a_line_is_right_and_quiet():
    x = _arcsine(20_000, 0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        value = entropy(x, method="ksg")
    assert value == pytest.approx(math.log(math.pi / 2), abs=0.05)


def test_kde_entropy_of_a_normal_sample_stays_quiet():
    x = np.random.default_rng(1).standard_normal(2_000)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        value = entropy(x, method="kde")
    assert value == pytest.approx(0.5 * math.log(2 * math.pi * math.e), abs=0.1)
