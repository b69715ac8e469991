"""Checks a command makes before its heavy imports (standard library only).

``python -m modalinfo``, ``python -m closedloop`` and ``python -m paper_figures`` import
NumPy, SciPy and numba before their own code runs; a process started in a folder that
has since been deleted failed there with a traceback (numba's import of coverage calls
``os.getcwd()``: audit 10-env). This module imports nothing of the project or beyond
the standard library, so the check costs nothing and comes first.
"""

from __future__ import annotations

import os
import sys

__all__ = ["require_current_folder"]


def require_current_folder(prog: str) -> None:
    """Exit with status 2 and one line on stderr if the current folder no longer exists.

    Parameters
    ----------
    prog : str
        The command's name, for the message (e.g. ``"modalinfo"``).
    """
    try:
        os.getcwd()
    except FileNotFoundError:
        sys.stderr.write(f"{prog}: error: the current folder no longer exists (deleted); "
                         "cd to an existing folder\n")
        sys.exit(2)
