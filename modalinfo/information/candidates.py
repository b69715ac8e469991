"""Which sources may inform which target: the candidate rule of the searches in time.

The transfer-entropy map (:func:`~modalinfo.information.transfer_entropy_map`), the
greedy input search (:func:`~modalinfo.information.select_inputs`) and the ``info``
predictor (:class:`~modalinfo.forecast.InfoPredictor`) score every (source mode, lag)
for every target: ``M^2 L`` cells, which is what stops them at thousands of modes.
This module restricts the sources of each target to those that physics makes
plausible, as a boolean mask ``allowed[j, i]`` (source j may inform target i):

- ``"all"``: every source (the default; the searches are then bit for bit what they
  were before the rule existed).
- ``"radial"``: modes whose radial orders differ by at most ``radial_width``. Frozen
  flow moves a phase screen across the pupil, and the temporal cross-correlation of
  two Zernike modes under it is an integral over spatial frequency f of the
  turbulence spectrum times ``J_{n+1}(2 pi f R) J_{n'+1}(2 pi f R)`` (Conan, Rousset &
  Madec 1995, JOSA A 12, 1559, their temporal cross-spectra): each Bessel factor
  peaks near ``2 pi f R ~ n + 1``, so the product, and with it the coupling, falls as
  the radial orders n and n' separate; the dominant couplings are those within a
  couple of orders (default width 2). A mode's radial order is read from its label:
  ``"Z<j>"`` is Noll index j (:func:`modalinfo.bases.noll_to_zernike`);
  ``"KL<k>"`` takes the radial order of Noll index ``k + 1`` (the equivalent radial
  order of the k-th K-L mode: :class:`~modalinfo.bases.KLBasis` is built on Noll
  ``j = 2, 3, ...`` and sorted by variance, which falls with the radial order); a
  second log's ``"extra:<label>"`` is read as ``<label>``. Any other label is refused
  (give an explicit mask).
- an explicit ``(S, S)`` boolean array ``allowed[j, i]``, e.g. the neighbours of a DM's
  actuators (:func:`neighbour_mask`, for DM-space modes or actuator telemetry: a DM
  couples neighbours).

A target's own past is always allowed (the diagonal is forced True). The rule is a
restriction of the family tested: the maximum-statistic tests of the map and of the
search then control the family-wise error over the restricted family
(``benchmarks/bench_flow_fwer.py --part restricted``).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

import numpy as np

from modalinfo.bases.indexing import noll_to_zernike
from modalinfo.common.validation import as_float_array, check_int, check_real

__all__ = ["CANDIDATE_RULES", "RADIAL_WIDTH", "candidate_mask", "neighbour_mask",
           "radial_orders"]

#: Named candidate rules (an explicit boolean mask is the third form).
CANDIDATE_RULES = ("all", "radial")
#: Default ``radial_width`` of the ``"radial"`` rule, for every function that takes it:
#: frozen flow couples modes within a couple of radial orders (module notes).
RADIAL_WIDTH = 2

_ZERNIKE = re.compile(r"^Z(\d+)$")
_KL = re.compile(r"^KL(\d+)$")


def radial_orders(labels: Sequence[str]) -> np.ndarray:
    """Radial order (or K-L equivalent radial order) of each mode label.

    Parameters
    ----------
    labels : sequence of str
        ``"Z<j>"`` (Noll j >= 1), ``"KL<k>"`` (k >= 1), optionally prefixed ``"extra:"``.

    Returns
    -------
    numpy.ndarray of int, shape (S,)
        Radial order n of ``Z<j>``; that of Noll ``k + 1`` for ``KL<k>``.

    Raises
    ------
    ValueError
        A label that is neither form (name it; give an explicit mask instead).
    """
    out = np.empty(len(labels), dtype=np.int64)
    for a, label in enumerate(labels):
        name = str(label).removeprefix("extra:")
        zm, km = _ZERNIKE.match(name), _KL.match(name)
        if zm and int(zm.group(1)) >= 1:
            out[a] = int(noll_to_zernike(int(zm.group(1)))[0])
        elif km and int(km.group(1)) >= 1:
            out[a] = int(noll_to_zernike(int(km.group(1)) + 1)[0])
        else:
            raise ValueError(f"candidates='radial' needs Zernike ('Z<j>', Noll) or K-L "
                             f"('KL<k>') mode labels; got {label!r} at column {a}: give an "
                             f"explicit (S, S) boolean mask as `candidates`.")
    return out


def neighbour_mask(positions: Any, radius: float) -> np.ndarray:
    """Return the candidate mask of a DM geometry: sources within ``radius`` of a target.

    Parameters
    ----------
    positions : array_like, shape (S, 2)
        Position of each series (e.g. actuator x, y) [m or pitches, as ``radius``].
    radius : float
        Largest distance between a source and its target, > 0.

    Returns
    -------
    numpy.ndarray of bool, shape (S, S)
        ``allowed[j, i]``: ``|p_j - p_i| <= radius`` (symmetric, True on the diagonal).
    """
    p = as_float_array(positions, "positions", ndim=2)
    if p.shape[1] != 2:
        raise ValueError(f"`positions` must have shape (S, 2); got {p.shape}.")
    radius = check_real(radius, "radius", minimum=0.0, strict_min=True)
    d2 = ((p[:, None, :] - p[None, :, :]) ** 2).sum(axis=-1)
    return d2 <= radius * radius


def candidate_mask(labels: Sequence[str], candidates: Any = "all",
                   radial_width: int = RADIAL_WIDTH) -> np.ndarray | None:
    """Return the ``(S, S)`` mask ``allowed[j, i]`` of a candidate rule (None: ``"all"``).

    Parameters
    ----------
    labels : sequence of str
        Labels of the S series (the log's, then ``"extra:<label>"``).
    candidates : {"all", "radial"} or array_like of bool, shape (S, S)
        The rule (module notes). An explicit mask is copied and its diagonal set True.
    radial_width : int
        Largest ``|n_j - n_i|`` of ``"radial"`` (>= 0).

    Returns
    -------
    numpy.ndarray of bool, shape (S, S), or None
        None means every source (the unrestricted path, bit for bit as before).

    Raises
    ------
    ValueError
        An unknown rule, a mask of the wrong shape, or labels ``"radial"`` cannot read.
    TypeError
        A mask that is not boolean.
    """
    S = len(labels)
    if isinstance(candidates, str):
        if candidates not in CANDIDATE_RULES:
            raise ValueError(f"`candidates` must be one of {CANDIDATE_RULES} or an (S, S) "
                             f"boolean mask; got {candidates!r}.")
        if candidates == "all":
            return None
        width = check_int(radial_width, "radial_width", minimum=0)
        n = radial_orders(labels)
        return np.abs(n[:, None] - n[None, :]) <= width
    mask = np.array(candidates, copy=True)
    if mask.dtype != bool:
        raise TypeError(f"`candidates` as a mask must be a boolean array; got dtype "
                        f"{mask.dtype}.")
    if mask.shape != (S, S):
        raise ValueError(f"`candidates` as a mask must have shape ({S}, {S}) (sources x "
                         f"targets); got {mask.shape}.")
    np.fill_diagonal(mask, True)
    return mask
