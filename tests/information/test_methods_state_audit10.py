"""The live views of the method names are not hashable (audit 10-state, row hash-METHODS).

Reference: Python's data model (a hashable object's hash must not change during its
lifetime; objects that compare equal have the same hash). ``METHODS`` compares equal to
the tuple of the names registered at the time of the call, so its hash changed at
``register_method`` and a dict holding it could no longer find it; it is now unhashable,
as a list is.
"""

import dataclasses

import pytest

from modalinfo.information import (
    CMI_METHODS,
    METHODS,
    register_method,
    unregister_method,
)
from modalinfo.information.methods import get_method


@pytest.mark.parametrize("view", [METHODS, CMI_METHODS])
def test_name_views_are_unhashable(view):
    with pytest.raises(TypeError, match="unhashable"):
        hash(view)
    with pytest.raises(TypeError):
        {view: 1}  # noqa: B018


def test_view_follows_the_registry():
    before = tuple(METHODS)
    register_method(dataclasses.replace(get_method("gaussian"), name="audit10_copy"))
    try:
        assert METHODS == before + ("audit10_copy",)
        assert "audit10_copy" in METHODS
    finally:
        unregister_method("audit10_copy")
    assert METHODS == before
