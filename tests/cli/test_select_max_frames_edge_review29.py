"""``select --max-frames`` exactly at the fewest frames the selection takes runs (review29).

Round 29 M3 (modalinfo/cli/cmd_select.py:137, fixes 45-c T74): the refusal applies below
``horizon + max_lag + 19`` frames (20 rows of lagged pairs). Planted as "at or below", it
passed every test (12 and 21 frames refused, none at 22). Reference: the rule's arithmetic
by hand, 1 + 2 + 19 = 22 frames; T - horizon - max_lag + 1 = 22 - 1 - 2 + 1 = 20 rows.
"""

from .conftest import exit_code, write_small_log


def test_max_frames_at_the_fewest_the_selection_takes_runs(tmp_path, capsys):
    log = write_small_log(tmp_path / "log.npz", 400)
    argv = ["select", log, "--target", "Z2", "--max-lag", "2", "--no-intervals",
            "--surrogates", "9", "--alpha", "0.2"]  # 10 shifts fit in 20 rows, 199 do not
    assert exit_code([*argv, "--max-frames", "22"]) == 0
    assert "need at least" not in capsys.readouterr().err
    assert exit_code([*argv, "--max-frames", "21"]) == 2  # one frame fewer: refused
    assert "need at least 22" in capsys.readouterr().err
