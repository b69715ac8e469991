"""Headerless dumps: a suffix in capitals, and a UTF-8 text .dat cut mid-character (round 38).

References: the bytes written here (numpy's ``ndarray.tofile``, a UTF-8 text whose
2-byte character "µ" starts at byte 511, so the 512-byte look the format detection
takes ends inside it; Python's ``str.encode`` tells the offset); the refusal names the
file's size in bytes and its float32 count (size / 4) as fix56-c states it, and a text
.dat is read as the CSV log it is (50 frames x 3 modes, numpy's ``savetxt`` rows). Each
test names the plant of docs/MUTATION.md's round 38 it fails with.
"""

import numpy as np

from modalinfo.cli import main


def test_a_dump_named_in_capitals_is_named_as_one(tmp_path, capsys):
    """R38-FO5: ``PX.RAW`` is the same headerless dump as ``px.raw``; R38-FO6: its counts."""
    path = tmp_path / "PX.RAW"
    frames = (np.random.default_rng(1).random((6, 32, 32)) * 4000).astype(np.float32)
    frames.tofile(path)
    size = path.stat().st_size
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "headerless binary dump" in err and f"{size:,} bytes" in err
    assert size % 8 == 0  # each count is the size over the type's width in bytes
    assert f"{size // 2:,} uint16, {size // 4:,} float32, {size // 8:,} float64 values" in err


def test_a_text_dat_cut_inside_a_character_at_byte_512_is_a_csv(tmp_path, capsys):
    """R38-FO3: a multi-byte character cut by the 512-byte look is not binary."""
    path = tmp_path / "cols.dat"
    comment = "#" + "x" * 509 + " µm\n"  # "µ" (2 bytes in UTF-8) starts at byte 511
    assert comment.encode().index("µ".encode()) == 511
    rows = np.random.default_rng(2).standard_normal((50, 3))
    text = comment + "\n".join(",".join(f"{v:.6f}" for v in r) for r in rows) + "\n"
    path.write_bytes(text.encode("utf-8"))
    assert main(["info", str(path), "--rate", "100"]) == 0
    assert "50 frames x 3 modes" in capsys.readouterr().out
