"""``closedloop.aot._other_code`` names the code that wrote a result (review30, round 30 A1).

Fixes 47-b (round 47 PART b V12 / W12) names, on a shape mismatch at export, the version
that wrote the result: its git revision, else the first 12 hex digits of its source
SHA-256, else "an older version"; tests/closedloop/test_mutation_gaps_aot.py reaches the
git and the no-record cases only, so a planted ``written[:8]`` passed every test.
Reference: the SHA-256 written here by hand (its first 12 characters counted by eye) and
this code's own ``provenance.code_record()`` (a result of this code: nothing said).
"""

from types import SimpleNamespace

from closedloop.aot import _other_code
from modalinfo.common.provenance import code_record

SHA = "0123456789abcdef" * 4


def test_a_source_without_git_is_named_by_twelve_digits():
    text = _other_code(SimpleNamespace(provenance={"source_sha256": SHA}))
    assert text.startswith(": the result was written by another version of the code "
                           "(source 0123456789ab), which built")


def test_a_result_of_this_code_says_nothing():
    here = code_record()["source_sha256"]
    assert _other_code(SimpleNamespace(provenance={"source_sha256": here, "git": "x"})) == ""
