"""The log-format error every reader raises.

:class:`LogFormatError` names the file and what is wrong with it. The file plumbing
that used to live here (atomic writes, path checks, sizes) is the ground floor's:
:mod:`modalinfo.common.files` and :mod:`modalinfo.common.sizes`.
"""

from __future__ import annotations

__all__ = ["LogFormatError"]


class LogFormatError(ValueError):
    """A file is not a readable log: truncated, corrupted or of an unexpected layout.

    A subclass of ``ValueError``; the message names the file and what is wrong.
    """
