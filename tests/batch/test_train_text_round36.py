"""Round 36 PART b, B03: ``--set forecast.train=+700`` says the value is JSON text.

Reference: the JSON grammar (RFC 8259: a number has no leading '+' and no bare leading
'.'), by which ``--set`` values are read, and ``modalinfo forecast --train +700``, which
reads 700 frames. Before the fix the refusal "must be ... a number of frames >= 2; got
'+700'" read as if 700 frames were refused.
"""

from modalinfo.cli import main


def test_batch_names_a_number_written_as_json_text(tmp_path, capsys, helpers):
    helpers.write_archive(tmp_path, n_good=1, corrupt=False)
    out = tmp_path / "out"
    code = main(["batch", str(tmp_path), "--analyses", "forecast", "--set",
                 "forecast.train=+700", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert ("got '+700' (a text: --set values are read as JSON, where a number is "
            "written 700)") in err
    assert not out.exists()
