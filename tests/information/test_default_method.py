"""The default MI / CMI estimator is KSG, as the docs say; its switch and size rules.

References: the documentation itself (README.md, docs/ARCHITECTURE.md and the
docstrings state the default; a change of default that forgets them fails here); the
explicit ``method="ksg"`` and ``method="gaussian"`` calls, which omitting ``method=``
must reproduce bit for bit (the switch returns the Gaussian-copula CMI, the method
``"gaussian"``); the published rules of the KSG CMI (conditional module notes, "Bias
rule": a neighbour ball of side (k / n)^(1/d) <= 0.4, i.e. n >= k 2.5^d, whose
boundary test_robust_defaults.py checks; at most 60 s of estimated CPU) and of its
size (ksg module notes, "Size rule": at most 10^6 samples, and memory within what is
available). Accuracy of the default against the exact MI: test_beyond_normal.py.
"""

import inspect
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from modalinfo.information import (
    BiasRuleWarning,
    MutualInformation,
    conditional_mutual_information,
    conditional_mutual_information_ci,
    conditional_mutual_information_test,
    mutual_information,
    mutual_information_ci,
    mutual_information_permutation_test,
)
from modalinfo.information import ksg as ksg_module
from modalinfo.information.conditional import bias_rule
from modalinfo.information.methods import check_bootstrappable

ROOT = Path(__file__).resolve().parents[2]


def _default(fn):
    return inspect.signature(fn).parameters["method"].default


@pytest.fixture(scope="module")
def groups():
    """2 x 2 Gaussian groups, n = 1500: x_i, y_i correlated 0.6."""
    rng = np.random.default_rng(27)
    x = rng.standard_normal((1500, 2))
    y = 0.6 * x + 0.8 * rng.standard_normal((1500, 2))
    return x, y


def test_the_point_estimates_default_to_ksg():
    for fn in (mutual_information, MutualInformation.__init__, conditional_mutual_information):
        assert _default(fn) == "ksg", fn.__qualname__


def test_the_resampling_functions_keep_the_histogram():
    # one estimate per resample: ksg cannot be bootstrapped, and 999 ksg permutations at
    # n = 1e4 cost ~1.5 min of CPU against ~1 s for the histogram
    for fn in (mutual_information_ci, conditional_mutual_information_ci,
               mutual_information_permutation_test, conditional_mutual_information_test):
        assert _default(fn) == "histogram", fn.__qualname__
    with pytest.raises(ValueError, match=r"`method`='ksg' cannot be bootstrapped"):
        check_bootstrappable("ksg", needs="cmi")


def test_the_docs_state_the_default():
    for fn in (mutual_information, conditional_mutual_information):
        assert 'Default ``"ksg"``' in " ".join(fn.__doc__.split()), fn.__name__
    readme = (ROOT / "README.md").read_text()
    assert 'default to `method="ksg"`' in readme
    assert 'default to method="ksg"' in (ROOT / "docs" / "ARCHITECTURE.md").read_text()


def test_omitting_method_is_ksg_bit_for_bit(groups):
    x, y = groups
    assert mutual_information(x[:, 0], y[:, 0]) == mutual_information(x[:, 0], y[:, 0],
                                                                      method="ksg")
    assert MutualInformation().estimate(x[:, 0], y[:, 1]) == \
        MutualInformation("ksg").estimate(x[:, 0], y[:, 1])
    assert conditional_mutual_information(x, y) == conditional_mutual_information(
        x, y, method="ksg")
    a = mutual_information_permutation_test(x[:300, 0], y[:300, 0], n_permutations=9, seed=1)
    b = mutual_information_permutation_test(x[:300, 0], y[:300, 0], "histogram",
                                            n_permutations=9, seed=1)
    assert a.statistic == b.statistic and a.pvalue == b.pvalue and a.method == "histogram"


def test_many_conditioning_columns_switch_the_default_to_the_gaussian_copula(groups):
    # n = 1500 over 1 + 1 + 10 columns: ball (3 / 1500)^(1/12) = 0.60 > 0.4
    x, y = groups
    z = np.random.default_rng(5).standard_normal((1500, 10))
    with pytest.warns(BiasRuleWarning, match=r"KSG CMI over 12 columns .* returning the "
                                             r"Gaussian-copula CMI instead"):
        value = conditional_mutual_information(x[:, 0], y[:, 0], z)
    assert value == conditional_mutual_information(x[:, 0], y[:, 0], z, method="gaussian")
    assert value == pytest.approx(-0.5 * math.log(1 - 0.6**2), abs=0.03)  # z independent
    with pytest.raises(ValueError, match=r"KSG CMI over 12 columns .*\(fallback='raise'\)"):
        conditional_mutual_information(x[:, 0], y[:, 0], z, fallback="raise")
    # 2 conditioning columns: (3 / 1500)^(1/4) = 0.21, the KSG itself, no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error", BiasRuleWarning)
        kept = conditional_mutual_information(x[:, 0], y[:, 0], z[:, :2])
    assert kept == conditional_mutual_information(x[:, 0], y[:, 0], z[:, :2], method="ksg",
                                                  fallback="none")


def test_the_cost_rule_switches_slow_ksg_cmi(groups, monkeypatch):
    # estimated ~100 s for 2 x 2 groups at n = 1e6 (measured 2 x 2 at 1e5: ~8 s)
    assert "cost rule" in bias_rule("ksg", 1_000_000, 4)
    assert bias_rule("ksg", 500_000, 4) is None
    assert bias_rule("ksg", 1_000_000, 2) is None  # a pair: 25 s, under the rule
    x, y = groups
    monkeypatch.setattr(ksg_module, "KSG_MAX_SECONDS", 1e-3)
    with pytest.warns(BiasRuleWarning, match=r"above its cost rule .* Gaussian-copula"):
        value = conditional_mutual_information(x, y)
    assert value == conditional_mutual_information(x, y, method="gaussian")


def test_the_size_rule_refuses_before_any_work():
    n = ksg_module.KSG_MAX_SAMPLES + 1
    x = np.random.default_rng(0).standard_normal(n)
    y = np.roll(x, 1)
    with pytest.raises(ValueError, match=r"method='ksg' on n = 1,000,001 samples over 2 "
                                         r"columns .* size rule \(at most 1,000,000 samples"):
        mutual_information(x, y)
    with pytest.raises(ValueError, match=r"size rule \(at most 1,000,000 samples\).*"
                                         r"x\[::m\] with m >= 2"):
        conditional_mutual_information(x, y)
    mutual_information(x[:2000], y[:2000])  # below the rule: no refusal


def test_the_size_rule_refuses_what_memory_cannot_hold(monkeypatch):
    monkeypatch.setattr(ksg_module, "_MEMORY_CHECKED_ABOVE", 0)
    monkeypatch.setattr(ksg_module, "available_memory_bytes", lambda: 1e5)
    seconds, nbytes = ksg_module.ksg_cost(2000, 2)
    assert nbytes > 1e5
    rng = np.random.default_rng(1)
    with pytest.raises(ValueError, match=r"memory within the 9.31e-05 GiB available"):
        mutual_information(rng.standard_normal(2000), rng.standard_normal(2000))
