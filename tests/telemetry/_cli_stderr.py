"""A command line's exit code and stderr lines, warnings shown as outside pytest."""

import sys
import warnings


def cli_stderr(argv, capsys) -> tuple[int, list[str]]:
    from modalinfo.cli import main

    capsys.readouterr()
    with warnings.catch_warnings():
        # as outside pytest (which records warnings, and the suite makes them errors):
        # Python's default showwarning writes formatwarning's text to stderr
        warnings.simplefilter("always")
        warnings.showwarning = lambda message, category, filename, lineno, file=None, \
            line=None: sys.stderr.write(warnings.formatwarning(message, category, filename,
                                                               lineno, line))
        code = main([str(a) for a in argv])
    return code, [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
