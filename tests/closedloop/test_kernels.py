"""The loop's numba kernels against the plain computations they replace, on random inputs.

Science step. Reference: the piston-removed variance over the pupil of the sum of the
shifted plane maps, written in plain numpy one direction at a time (fancy-indexed 4 x 4
reads with ``closedloop.optics.science.read_weights``, a copy at whole pixels; two-pass
``numpy.var``): the computation the kernel replaces, as in
``benchmarks/bench_closedloop.py``. The kernel reads direction-independent planes once
and accumulates per pupil column, so it agrees with the reference to rounding only.

DM synthesis. Reference: the matrix product ``shapes @ c``; the kernel reads one
quadrant of the disc and the modes' parities, so again rounding only.

WFS products. Reference: scipy's CSR product, which the kernel reproduces bit for bit
(same order of additions in every row).
"""

import numpy as np
import pytest
from scipy import sparse

from closedloop import presets
from closedloop.config import DMConfig
from closedloop.kinds import mirror_kind
from closedloop.optics import _kernels
from closedloop.optics.geometry import Geometry
from closedloop.optics.science import ScienceCamera, read_weights


def plain_numpy(cam, weights):
    """Mean and variance per direction, plain numpy (the benchmark's reference step)."""
    n = cam.geometry.n_pixels
    jj, ii = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
    mask = cam.geometry.pupil_mask
    cols, rows = jj[mask], ii[mask]
    mean = np.empty(len(cam.directions))
    var = np.empty(len(cam.directions))
    for d in range(len(cam.directions)):
        v = np.zeros(cols.size)
        for p, view in enumerate(cam.plane_views()):
            fc, fr = cam._shifts[d, p]
            ic, ir = int(np.floor(fc)), int(np.floor(fr))
            r0, c0 = rows + ir, cols + ic
            if fc == ic and fr == ir:
                v += weights[p] * view[r0, c0]
                continue
            wx, wy = read_weights(fc - ic), read_weights(fr - ir)
            for a in range(4):
                for b in range(4):
                    v += weights[p] * wy[a] * wx[b] * view[r0 + a - 1, c0 + b - 1]
        mean[d] = v.mean()
        var[d] = v.var()
    return mean, var


@pytest.fixture(scope="module", params=["table1", "mcao3"])
def camera(request):
    geometry = Geometry(presets.get(request.param))
    return ScienceCamera(geometry, geometry.directions)


@pytest.mark.parametrize("piston", [0.0, 50.0])
@pytest.mark.parametrize("weights", [None, (1.0, 0.0, 1.0), (0.5, 2.0, -1.0)])
def test_kernel_matches_plain_numpy_on_random_maps(camera, piston, weights):
    n_planes = len(camera._sizes)
    w = np.ones(n_planes) if weights is None else np.resize(np.array(weights), n_planes)
    rng = np.random.default_rng(3)
    camera._flat[:] = rng.standard_normal(camera._flat.size) + piston
    got = camera.forward(None if weights is None else w).copy()
    mean, var = plain_numpy(camera, w)
    # a large common piston must not cost accuracy (moments taken about a pupil pixel)
    np.testing.assert_allclose(got, var, rtol=1e-12)
    np.testing.assert_allclose(camera.mean, mean, rtol=1e-12, atol=1e-12)


def test_ground_plane_is_read_once_and_threads_give_the_same_bits(camera):
    # the ground plane sits at the same place for every direction, the others do not
    assert camera._common[0] and not camera._common[1:].any()
    camera._flat[:] = np.random.default_rng(4).standard_normal(camera._flat.size)
    args = (camera._flat, camera._offsets, camera._sizes, camera._span_lo, camera._span_hi,
            camera._shifts, camera._taps, np.ones(len(camera._sizes)), camera._common,
            camera._base)
    out = [np.empty((2, len(camera.directions))) for _ in range(2)]
    _kernels.direction_moments_serial(*args, out[0][0], out[0][1])
    _kernels.direction_moments(*args, out[1][0], out[1][1])
    np.testing.assert_array_equal(out[0], out[1])
    # treating no plane as common (every plane read per direction) changes rounding only
    flags = np.zeros_like(camera._common)
    other = np.empty((2, len(camera.directions)))
    _kernels.direction_moments_serial(*args[:8], flags, camera._base, other[0], other[1])
    np.testing.assert_allclose(other, out[0], rtol=1e-13)


@pytest.mark.parametrize("name", ["table1", "mcao3"])
def test_dm_surface_from_one_quadrant_matches_the_matrix_product(name):
    geometry = Geometry(presets.get(name))
    rng = np.random.default_rng(5)
    for i in range(len(geometry.config.dms)):
        dm = mirror_kind(geometry.config.dms[i].kind).build(geometry, i)
        assert dm._mirror is not None  # even plane sides: the fast path is taken
        for _ in range(3):
            c = rng.standard_normal(dm.n_modes)
            ref = dm.shapes @ c
            np.testing.assert_allclose(dm.forward(c), ref, rtol=0,
                                       atol=1e-14 * np.max(np.abs(ref)))
        # one mode at a time: its own shape, sign and all
        for j in (0, 1, 2, dm.n_modes - 1):
            e = np.zeros(dm.n_modes)
            e[j] = 1.0
            np.testing.assert_allclose(dm.forward(e), dm.shapes[:, j], rtol=0, atol=1e-12)


def test_dm_surface_without_symmetry_falls_back_to_the_product():
    cfg = presets.get("table1")
    geometry = Geometry(cfg.replace(dms=(DMConfig(altitude=0.0, n_modes=20),
                                         DMConfig(altitude=10_000.0, n_modes=9))))
    dm = mirror_kind(geometry.config.dms[0].kind).build(geometry, 0)
    # 3228 x 20 shapes (0.5 MB) stay in cache: the plain product, its bits
    assert dm._mirror is None
    np.testing.assert_array_equal(dm.forward(np.ones(20)), dm.shapes @ np.ones(20))
    # a disc that is not symmetric: the tables refuse it and surface() is B c
    from closedloop.optics.dm import _mirror_tables

    n = geometry.planes[dm.plane].n
    assert _mirror_tables(dm.pixels[1:], dm.shapes[1:], n) is None
    assert _mirror_tables(dm.pixels, dm.shapes, n + 1) is None
    dm._mirror = None
    c = np.arange(20.0)
    np.testing.assert_array_equal(dm.forward(c), dm.shapes @ c)


@pytest.mark.parametrize("n_rows", [1, 4, 7, 13])
def test_csr_matvec_has_scipys_bits(n_rows):
    rng = np.random.default_rng(n_rows)
    a = sparse.random(n_rows, 300, density=0.2, format="csr", random_state=rng)
    a.data = rng.standard_normal(a.nnz) * 1e3
    b = sparse.random(n_rows, 50, density=0.5, format="csr", random_state=rng)
    x = rng.standard_normal(300) * 7.0
    y = rng.standard_normal(50)
    out = np.full(n_rows, np.nan)
    args = [(m.indptr.astype(np.int64), m.indices.astype(np.uint32), m.data) for m in (a, b)]
    _kernels.csr_matvec(*args[0], x, out, False)
    np.testing.assert_array_equal(out, a @ x)
    _kernels.csr_matvec(*args[1], y, out, True)
    ref = a @ x
    ref += b @ y
    np.testing.assert_array_equal(out, ref)


def test_wfs_slopes_have_the_sparse_products_bits():
    from closedloop import LoopModel

    from .conftest import small

    model = LoopModel(small())
    rng = np.random.default_rng(8)
    maps = [rng.standard_normal((p.n, p.n)) for p in model.geometry.planes]
    for wfs in model.wfss:
        noise = rng.standard_normal(wfs.n_measurements)
        ref = wfs.operators[0] @ maps[0].ravel()
        for op, r in zip(wfs.operators[1:], maps[1:], strict=True):
            ref += op @ r.ravel()
        ref += wfs.noise_rms * noise
        np.testing.assert_array_equal(wfs.forward(maps, noise), ref)
        with pytest.raises(ValueError, match="maps"):
            wfs.forward(maps[:1])


def test_one_direction_every_plane_common():
    # a single direction: every plane has "the same shift in every direction", so the
    # whole sum goes into the base map and no plane is interpolated per direction
    geometry = Geometry(presets.get("table1"))
    cam = ScienceCamera(geometry, np.array([[20.0, -35.0]]))
    assert cam._common.all()
    cam._flat[:] = np.random.default_rng(6).standard_normal(cam._flat.size) + 10.0
    mean, var = plain_numpy(cam, np.ones(len(cam._sizes)))
    np.testing.assert_allclose(cam.forward(), var, rtol=1e-12)
    np.testing.assert_allclose(cam.mean, mean, rtol=1e-12)


@pytest.mark.parametrize("name", ["mcao3", "est-mcao@16"])
def test_the_shared_row_sums_give_the_kernels_bits(name):
    # reference: the kernel without groups (itself checked against plain numpy above);
    # directions on one row of the field grid share each plane's 4-row sums, the same
    # operations on the same numbers, so the same bits, with any plane weights
    cfg = presets.est_mcao_variant(16) if name.startswith("est") else presets.get(name)
    geometry = Geometry(cfg)
    cam = ScienceCamera(geometry, geometry.directions)
    assert cam._groups is not None and not cam._parallel
    n_dir = len(cam.directions)
    assert len(cam._groups[1]) < n_dir * int(np.sum(~cam._common))  # reads are shared
    rng = np.random.default_rng(6)
    cam._flat[:] = rng.standard_normal(cam._flat.size) + 40.0
    for w in (np.ones(len(cam._sizes)), rng.uniform(-1.0, 2.0, len(cam._sizes))):
        args = (cam._flat, cam._offsets, cam._sizes, cam._span_lo, cam._span_hi, cam._shifts,
                cam._taps, w, cam._common, cam._base)
        ref = np.empty((2, n_dir))
        _kernels.direction_moments_serial(*args, ref[0], ref[1])
        got = cam.forward(w)
        np.testing.assert_array_equal(got, ref[1])
        np.testing.assert_array_equal(cam.mean, ref[0])
