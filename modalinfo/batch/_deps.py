"""Import the optional dependencies of ``modalinfo.batch`` with an error naming the extra."""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["require"]

_EXTRA = "dist"


def require(module: str) -> ModuleType:
    """Import ``module`` (``distributed``, ``pyarrow``...) or explain how to install it.

    Raises
    ------
    ImportError
        Naming the module and the extra: ``pip install 'modalinfo[dist]'``.
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise ImportError(
            f"modalinfo batch needs the optional dependency '{module.split('.')[0]}' "
            f"(not importable: {exc}); install it with: pip install 'modalinfo[{_EXTRA}]'"
        ) from None
