"""``MethodNames.refusal`` speaks only of a built-in that is unregistered (review28).

Its docstring: "Return the refusal of a built-in ``name`` unregistered in this process,
else None". Planted bug R28-B4 (the ``not in _REGISTRY`` test dropped) escaped
``test_replaced_builtin_round45.py``: its one caller, ``check_choice``, asks only for a
name not among the choices. Reference: the docstring and the built-in names of the
package (``gaussian`` is registered when ``modalinfo.information`` is imported).
"""

from modalinfo.information.methods import METHODS


def test_a_registered_builtin_and_an_unknown_name_have_no_refusal():
    assert "gaussian" in METHODS
    assert METHODS.refusal("gaussian", "method") is None
    assert METHODS.refusal("no-such-method", "method") is None
