r"""The grid hint's ``\uXXXX`` escape of a C1 control reads back (review32, round 32).

Planted-bug review of fix49-c (``closedloop/sweep.py``'s ``_toml_config_line``):
fix49-c's names held ESC and U+2028 (whose escapes ``tomli_w`` writes itself, or have
four hex digits anyway), never a C1 control (U+0080-U+009F), so ``\u{:02x}`` (R32-S2,
``\u85``: not TOML) passed them. Reference: ``tomllib.loads`` of the hinted line gives
the name back, and the line is one printable line.
"""

from __future__ import annotations

import tomllib

import pytest

from closedloop import presets
from closedloop.config import save_config
from closedloop.sweep import load_grid


@pytest.mark.parametrize("name", ["c1\x85.toml", "c1\x9b[1m.toml", "tab\t.toml"])
def test_a_c1_control_in_the_name_reads_back(tmp_path, name):
    path = save_config(presets.get("kaos"), tmp_path / name)
    with pytest.raises(ValueError, match="is a closedloop config, not a sweep grid") as err:
        load_grid(path)
    message = str(err.value)
    assert message.isprintable(), message
    line = message.split("grid file, ", 1)[1].split(" (`closedloop sweep --help`", 1)[0]
    assert tomllib.loads(line) == {"config": name}
