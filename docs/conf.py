"""Sphinx configuration of the API reference site (build: see README "Documentation").

The API pages are generated at build time from each public package's ``__all__``
(``PUBLIC`` below), so the site follows the code: a name added to ``__all__`` gets its
page, a name removed loses it. ``tests/test_docs.py`` builds the site with warnings
as errors (``-W -n``).
"""

from __future__ import annotations

import importlib
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

project = "modalinfo"
author = "the modalinfo developers"
copyright = "2026, the modalinfo developers"  # noqa: A001 - Sphinx's name
release = importlib.import_module("modalinfo").__version__

extensions = [
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.mathjax",
    "numpydoc",
    "myst_parser",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "MUTATION.md"]
html_theme = "alabaster"
html_static_path: list[str] = []
templates_path = ["_templates"]

# numpydoc carries the types in the docstrings; signatures stay short and unlinked
autodoc_typehints = "none"
autosummary_generate = True
autosummary_imported_members = True
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
# numpydoc links the names of an "Attributes" section, and a class's own ``:meth:`fit```
# is resolved against the module that defines the class, while the API pages document
# classes under their public package path (``modalinfo.bases.KLBasis``): such bare or
# ``Class.member`` names are the documented class's own members, not broken links.
nitpick_ignore_regex = [
    (r"py:(obj|meth|attr)", r"[A-Za-z_]\w*"),
    (r"py:(meth|attr)", r"[A-Z]\w*\.\w+"),
    # closedloop's modules get their pages after its restructure (rooms)
    (r"py:mod", r"closedloop\.\w+"),
    # the optics room documents granulation, shifts and correlating only (PUBLIC below)
    (r"py:mod", r"closedloop\.optics\.(atmosphere|dm|geometry|phase_screen|science|wfs)"),
    # private modules (numba kernels) never get pages
    (r"py:(mod|func|obj)", r"closedloop(\.\w+)*\._\w+(\.\w+)*"),
]
# headings such as "### `closedloop`" in the markdown pages get anchors for links
myst_heading_anchors = 3

#: (page, package, one line): every public package whose ``__all__`` is documented.
PUBLIC = [
    ("modalinfo", "modalinfo.bases", "Pupils, Zernike polynomials, K-L bases, turbulence"),
    ("modalinfo", "modalinfo.telemetry", "ModalLog, units, sampling, summaries"),
    ("modalinfo", "modalinfo.telemetry.synthetic", "Synthetic open- and closed-loop logs"),
    ("modalinfo", "modalinfo.servo", "The integrator-loop servo model"),
    ("modalinfo", "modalinfo.io", "Readers and writers of logs"),
    ("modalinfo", "modalinfo.io.aot_system", "AO Telemetry systems"),
    ("modalinfo", "modalinfo.information", "Mutual information and entropy"),
    ("modalinfo", "modalinfo.information.methods", "The registry of MI methods"),
    ("modalinfo", "modalinfo.information.resampling",
     "Block bootstrap, block length and surrogate shifts"),
    ("modalinfo", "modalinfo.information.candidates",
     "Candidate sources of the information-in-time searches (radial order, masks)"),
    ("modalinfo", "modalinfo.ordering", "Orderings of modal bases, fitting error"),
    ("modalinfo", "modalinfo.forecast", "Predictors and their evaluation"),
    ("modalinfo", "modalinfo.batch", "Archives on Dask"),
    ("closedloop", "closedloop", "The MCAO simulator"),
    ("closedloop", "closedloop.optics.granulation", "Synthetic solar granulation scenes"),
    ("closedloop", "closedloop.optics.shifts", "Image-shift measurement (SDF, ADF^2, CFI)"),
    ("closedloop", "closedloop.kinds", "The registry of sensor and mirror kinds"),
    ("closedloop", "closedloop.optics.correlating",
     "Correlating Shack-Hartmann: image formation"),
    ("closedloop", "closedloop.optics.photon_budget",
     "The photon budget of a solar WFS pixel"),
    ("closedloop", "closedloop.optics.image_sampling",
     "Sampling of a correlating SH's subaperture image"),
    ("closedloop", "closedloop.optics.correlating_sensor",
     "The correlating Shack-Hartmann as a loop part (kind 'correlating')"),
]


def _api_pages(srcdir: Path) -> None:
    """Write ``api/<package>.rst`` (an autosummary of ``__all__``) and ``api/index.rst``."""
    out = srcdir / "api"
    out.mkdir(exist_ok=True)
    index = [
        "API reference",
        "=============",
        "",
        "Generated from each package's ``__all__``.",
        "",
    ]
    for top in ("modalinfo", "closedloop"):
        index += [top, "-" * len(top), "", ".. toctree::", "   :maxdepth: 1", ""]
        for page, package, line in PUBLIC:
            if page != top:
                continue
            module = importlib.import_module(package)
            names = sorted(n for n in module.__all__ if not _is_module(module, n))
            title = f"``{package}``: {line}"
            text = [title, "=" * len(title), "", f".. automodule:: {package}", "",
                    f".. currentmodule:: {package}", "", ".. autosummary::",
                    "   :toctree: generated", "   :nosignatures:", ""]
            text += [f"   {name}" for name in names]
            _write(out / f"{package}.rst", "\n".join(text) + "\n")
            index.append(f"   {package}")
        index.append("")
    _write(out / "index.rst", "\n".join(index))


def _is_module(module, name: str) -> bool:
    return type(getattr(module, name)).__name__ == "module"


def _write(path: Path, text: str) -> None:
    """Write only when changed, so that Sphinx does not rebuild every page."""
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


# now, before Sphinx looks for source files (autosummary then writes the stubs)
_api_pages(Path(__file__).resolve().parent)
