"""``policy_record`` refuses what it cannot answer (round 36 PART a, T1 / T2; round 37 M1-M3).

Reference: the record ``apply_outlier_policy`` appends to ``metadata["outliers"]`` (a
round trip: ``policy_record`` must return it unchanged), and the contract of the
common brief (bad input: an error naming the argument). Before the fix a log that never
went through the policy, or ``policy="bogus"``, raised ``KeyError: 'outliers'``.
"""

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog
from modalinfo.telemetry.quality import apply_outlier_policy, assess_quality, policy_record


def _spiked() -> ModalLog:
    x = np.random.default_rng(0).standard_normal((3000, 4))
    x[100, 2] = 1e4
    return ModalLog(x, rate=1000.0)


def test_applied_log_returns_its_record():
    log = _spiked()
    out, report = apply_outlier_policy(log, "warn")
    assert not report.clean
    assert policy_record(report, out, "warn") == out.metadata["outliers"][-1]


def test_log_without_record_refused_naming_log():
    log = _spiked()
    with pytest.raises(ValueError, match="`log` holds no outlier-policy record"):
        policy_record(assess_quality(log), log, "warn")


def test_unknown_policy_refused_naming_policy():
    log = _spiked()
    with pytest.raises(ValueError, match="`policy`"):
        policy_record(assess_quality(log), log, "bogus")


# round 37 PART a, M1-M3: the record returned must be the one of the policy asked and of
# the report given (reference: the record apply_outlier_policy appended, and the brief's
# contract - a wrong argument is refused by name)

@pytest.mark.parametrize("asked", ["drop", "warn"])
def test_record_of_another_policy_refused_naming_policy(asked):
    out, report = apply_outlier_policy(_spiked(), "clip")
    assert policy_record(report, out, "clip") == out.metadata["outliers"][-1]
    with pytest.raises(ValueError, match=rf"`policy` is '{asked}'.*of policy 'clip'"):
        policy_record(report, out, asked)


def test_report_of_another_log_refused_naming_report():
    out, _ = apply_outlier_policy(_spiked(), "clip")
    x = np.random.default_rng(1).standard_normal((3000, 3))
    x[200, 1] = 1e4
    other = assess_quality(ModalLog(x, rate=1000.0))
    assert not other.clean
    with pytest.raises(ValueError, match="`report` is not the assessment"):
        policy_record(other, out, "clip")
