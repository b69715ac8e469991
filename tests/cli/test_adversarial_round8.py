"""Round 8 of issue 27's adversarial inputs (command lines): failures, fixed.

The full list of inputs tried is in docs/ADVERSARIAL.md, section "Round 8, issue 27".

Reference: the dispatcher contract (one line on stderr, exit 2, no traceback) and the
AOT format: a loop whose coefficients carry labels but no ``modes`` data (the mode
images) holds no modal basis, which the message must say without contradicting
``modalinfo info`` (which lists the labels).
"""

from __future__ import annotations

import pytest

pytest.importorskip("aotpy")

from .conftest import exit_code  # noqa: E402
from .test_cli_aot import naomi_file  # noqa: E402, F401  (the shared AOT fixture)


def test_reorder_basis_file_of_a_loop_without_mode_images_says_so(naomi_file, capsys):  # noqa: F811
    # e122: an exported DM-K-L run (coefficients DMKL1..40, no mode images) was refused
    # with "loop 'dm0.pol' has no modes" while `modalinfo info` listed its 40 modes
    code = exit_code(["reorder", naomi_file, "--loop", "Other", "--basis", "file", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert "has no mode images" in err and "no modal basis can be read" in err
