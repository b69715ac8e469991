"""Round 16 PART b (issue 27): files other tools read, and launch modes.

References from outside the code: RFC 8259 JSON as Python's own strict reader applies it
(``json.loads`` with a ``parse_constant`` that refuses ``NaN`` / ``Infinity``, the tokens
strict readers such as ``jq`` and JavaScript's ``JSON.parse`` reject) and IEEE 754
(``math.isnan`` / ``math.isinf`` of the value read back); for the launch mode, CPython's
documented ``-X warn_default_encoding`` and ``-W error::EncodingWarning`` (PEP 597) in a
fresh interpreter, whose exit status and stderr are the user's.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

from modalinfo.common.tasks.rows import RowStore

ROOT = Path(__file__).resolve().parents[2]


def _refuse(token: str) -> None:
    raise ValueError(f"non-strict JSON token {token}")


def test_row_files_are_strict_json_and_read_back_nan_and_inf(tmp_path):
    # a summary row of an all-constant log has lag1 NaN (round 16 PART b, J01)
    store = RowStore(tmp_path)
    row = {"status": "ok", "lag1_median": math.nan, "top": math.inf, "low": -math.inf,
           "rms": 0.25, "nested": [1.0, math.nan], "path": "a.npz"}
    path = store.write("k1", row)
    text = path.read_text(encoding="utf-8")
    data = json.loads(text, parse_constant=_refuse)  # raises on NaN / Infinity tokens
    assert data["lag1_median"] is None and data["rms"] == 0.25
    (back,) = store.rows()
    assert math.isnan(back["lag1_median"])
    assert back["top"] == math.inf and back["low"] == -math.inf
    assert back["rms"] == 0.25 and back["path"] == "a.npz" and back["key"] == "k1"
    assert back["nested"][0] == 1.0 and back["nested"][1] is None  # strict; not restored
    assert "_nonfinite" not in back


def test_rows_of_an_older_version_with_nan_tokens_still_read(tmp_path):
    store = RowStore(tmp_path)
    (tmp_path / "rows" / "old.json").write_text('{"key":"old","x":NaN,"status":"ok"}',
                                                 encoding="utf-8")
    (back,) = store.rows()
    assert math.isnan(back["x"]) and store.finished() == {"old"}


def test_commands_start_under_warn_default_encoding_as_errors(tmp_path):
    # numba's own open() without an encoding was re-emitted by modalinfo.common.jit and,
    # under -W error::EncodingWarning, every command died in a traceback (I10-I12)
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    env.pop("PYTHONWARNINGS", None)
    code = "import modalinfo.common.jit, closedloop.config; print('ok')"
    out = subprocess.run([sys.executable, "-X", "warn_default_encoding", "-W",
                          "error::EncodingWarning", "-c", code], capture_output=True,
                         text=True, env=env, cwd=tmp_path, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.strip() == "ok" and "Traceback" not in out.stderr
