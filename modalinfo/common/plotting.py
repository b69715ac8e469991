"""The user's matplotlib configuration, made drawable on this machine.

Every figure modalinfo, ``closedloop`` and ``paper_figures`` write is drawn inside
:func:`drawable_rc`. A ``matplotlibrc`` (or style) can ask for what this machine cannot
give; round 19 PART b found two:

* ``text.usetex: True`` without a LaTeX installation: matplotlib raised a
  ``RuntimeError`` traceback at the first label, after the work was done (``modalinfo
  fitting-error --plot`` exited 0 without its figure, ``modalinfo forecast --out`` and
  ``paper_figures`` lost the whole run);
* a ``font.family`` that is not installed: matplotlib's ``findfont`` logged one line per
  text drawn (197 lines for one figure, 558 for ``forecast --out``).

Both are overridden for the drawing only (``matplotlib.rc_context``: the caller's
settings are unchanged afterwards), with one warning per process naming the setting
and why. Every other setting of the user's (colours, styles, line widths) is kept.
"""

from __future__ import annotations

import contextlib
import os
import shutil
from collections.abc import Iterator

from modalinfo.common.quiet import warn

__all__ = ["drawable_rc", "plot_text", "rc_overrides"]

#: warnings already given in this process (one per problem, however many figures)
_WARNED: set[str] = set()


def _warn_once(key: str, message: str) -> None:
    if key not in _WARNED:
        _WARNED.add(key)
        warn(message, UserWarning, stacklevel=3)


def _found(family: str) -> bool:
    """Say whether matplotlib finds ``family`` (a name or a generic family) without fallback."""
    from matplotlib import font_manager

    try:
        font_manager.findfont(font_manager.FontProperties(family=[family]),
                              fallback_to_default=False)
    except ValueError:
        return False
    return True


#: LaTeX's special characters in text mode and what typesets each as itself (the ten
#: of Lamport's "LaTeX", Sect. 2.2.1, with ``<``, ``>`` and ``|``, which OT1 fonts set
#: as other glyphs): what a user's text becomes under ``text.usetex: True``
_TEX_TEXT = {"\\": r"\textbackslash{}", "{": r"\{", "}": r"\}", "$": r"\$", "&": r"\&",
             "%": r"\%", "#": r"\#", "_": r"\_", "^": r"\textasciicircum{}",
             "~": r"\textasciitilde{}", "<": r"\textless{}", ">": r"\textgreater{}",
             "|": r"\textbar{}"}


def plot_text(text: str | os.PathLike, *, usetex: bool | None = None) -> str:
    r"""Return a user's text (a file name, a mode label) for a matplotlib title or label.

    Drawn raw, a name holding two ``$`` (``$x$.npz``) was typeset as mathtext (an
    italic *x*), one that is not valid mathtext (``a$^$b``) stopped the drawing with a
    ``ValueError``, and a control character showed as a box or split the title (stop
    56, fix49-c's left item). Here the text is
    :func:`modalinfo.common.files.shown_name`'s one printable line (``\n``, ``\xNN``,
    ``\\``) with every ``$`` written ``\$``, which matplotlib draws as a ``$`` and never
    reads as mathtext (``matplotlib.cbook.is_math_text`` counts unescaped ``$`` only).

    Under ``text.usetex: True`` (kept by :func:`drawable_rc` where LaTeX is installed)
    TeX reads the whole text: an unescaped ``_``, ``&`` or ``#`` is a TeX error, a
    ``%`` starts a comment (not measured here: no LaTeX on the test machine; stop 57,
    fix51-c). There every
    special character of LaTeX's text mode is written as what typesets it
    (:data:`_TEX_TEXT`: ``\_``, ``\%``, ``\textbackslash{}`` ...).

    Parameters
    ----------
    text : str or os.PathLike
        The user's text as given.
    usetex : bool or None
        Escape for LaTeX (True) or for mathtext (False); None: as
        ``matplotlib.rcParams["text.usetex"]`` is now, so call this where the figure is
        drawn (inside :func:`drawable_rc` or the caller's ``rc_context``).

    Returns
    -------
    str
        The text to hand to ``set_title`` / ``set_xlabel`` / ``set_ylabel`` (and to join
        with the package's own words, which hold none of these characters).
    """
    from modalinfo.common.files import shown_name

    shown = shown_name(text)
    if usetex is None:
        import matplotlib

        usetex = bool(matplotlib.rcParams["text.usetex"])
    if usetex:
        return "".join(_TEX_TEXT.get(char, char) for char in shown)
    return shown.replace("$", "\\$")


def rc_overrides() -> dict:
    """Return the rcParams that replace settings this machine cannot draw with.

    Returns
    -------
    dict
        ``{"text.usetex": False}`` when the configuration asks for LaTeX text and no
        ``latex`` / ``dvipng`` is on ``PATH``; ``{"font.family": [...]}`` without the
        families matplotlib cannot find (matplotlib's default family when none is left).
        Empty when the configuration draws as it is. Each override is announced once per
        process by a ``UserWarning``.
    """
    import matplotlib

    rc = matplotlib.rcParams
    out: dict = {}
    if rc["text.usetex"]:
        missing = [tool for tool in ("latex", "dvipng") if shutil.which(tool) is None]
        if missing:
            out["text.usetex"] = False
            _warn_once("usetex", (
                f"the matplotlib configuration sets text.usetex: True but {' and '.join(missing)} "
                f"{'is' if len(missing) == 1 else 'are'} not installed; the figures are drawn "
                "with matplotlib's own text instead"))
    families = list(rc["font.family"])
    kept = [f for f in families if _found(f)]
    if kept != families:
        lost = [f for f in families if f not in kept]
        out["font.family"] = kept or list(matplotlib.rcParamsDefault["font.family"])
        _warn_once("font:" + ",".join(lost), (
            f"the matplotlib configuration asks for font family {', '.join(map(repr, lost))}, "
            f"not installed here; the figures use {', '.join(out['font.family'])} instead"))
    return out


@contextlib.contextmanager
def drawable_rc() -> Iterator[None]:
    """Draw (create, lay out and save figures) inside this context.

    The user's matplotlib settings apply, except those :func:`rc_overrides` replaces;
    the settings are restored on exit.
    """
    import matplotlib

    with matplotlib.rc_context(rc_overrides()):
        yield
