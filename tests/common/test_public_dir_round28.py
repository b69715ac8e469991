"""``dir()`` of every public package lists its whole ``__all__``, lazy names included.

Adversarial round 28 PART a, issue 27 (the API as a user discovers it): ``dir()`` and
IPython's tab completion read a module's ``__dir__``; ``modalinfo.telemetry`` imports
``synthetic`` and ``modalinfo.batch`` ``BatchResult`` / ``analyse_archive`` lazily
(module ``__getattr__``), and ``dir()`` did not show them.

Reference, outside the code under test: each package's documented ``__all__`` and
``getattr`` on each name (the name must resolve and be listed by ``dir``).
"""

from __future__ import annotations

import importlib

import pytest

PACKAGES = ["modalinfo", "modalinfo.telemetry", "modalinfo.forecast",
            "modalinfo.information", "modalinfo.ordering", "modalinfo.bases", "modalinfo.io",
            "modalinfo.batch", "closedloop"]


@pytest.mark.parametrize("name", PACKAGES)
def test_dir_lists_all_public_names(name):
    module = importlib.import_module(name)
    listed = set(dir(module))
    for public in module.__all__:
        getattr(module, public)
        assert public in listed, f"{name}.{public} is not in dir({name})"
