"""``closedloop sweep`` resumed in a folder whose runs another version of the code wrote says so.

Round 47 PART b V16, W16, V23: a sweep folder of 351d5180 / 4c25775f resumed by today's code
ran every entry again (task keys carry the source fingerprint, round 15 PART b) and printed
"2 runs: 0 already done, 2 ran" (V23: "4 runs: 0 already done, 4 ran" where 1 was finished)
without a word of the earlier runs set aside in rows/. Reference: the folder's own row files
(their key, override, seed and predictor) against the rows of this run; the sweep itself is
replaced by a stub returning those rows, so no simulation runs.
"""

from .conftest import sweep_row


def test_runs_of_other_code_are_counted(stubbed_sweep):
    now = [sweep_row("a" * 64, 0), sweep_row("b" * 64, 1)]
    old = [sweep_row("c" * 64, 0), sweep_row("d" * 64, 1),
           {**sweep_row("e" * 64, 2), "seed": 7, "override": "other grid"}]
    rows, lines = stubbed_sweep(now + old, now)
    assert lines[0].startswith("2 runs: 0 already done, 2 ran")
    # the two runs of the same entries under other keys; the other grid's row is not counted
    assert lines[1].startswith(f"  2 earlier run(s) in {rows} of these")


def test_a_plain_resume_says_nothing_more(stubbed_sweep):
    now = [sweep_row("a" * 64, 0)]
    _, lines = stubbed_sweep(now, now, skipped=1)
    assert not [line for line in lines if "earlier run" in line]
