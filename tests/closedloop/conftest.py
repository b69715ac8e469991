"""Configs shared by the closedloop tests (reference: none; configs only).

One copy of each small config that several test files run:

- :func:`shrunk`: a preset's layout on a small pupil, few modes and subapertures;
- :func:`small`: ``shrunk`` table1 (or another preset) at the sizes of the MCAO loop tests
  (test_loop, test_guards, test_predictor_faults, and the files that run it);
- :func:`lag_only`: a loop whose only error is the servo lag (test_laws_budget,
  test_budget_terms);
- :func:`tiny_actuator_loop`: table1 scaled down to one ground layer and a 9 x 9 actuator DM
  (:func:`tiny_actuator_config` for the test files of other folders);
- :func:`gap_config`, :func:`gap_sensor`: the small 4-m loops of the mutation-gap tests
  (test_mutation_gaps_model, test_mutation_gaps_wfs), built from their layers, mirrors
  and sensors;
- :func:`correlating_config`, :func:`correlating_sensor`: the small frozen-turbulence
  loops of the correlating-sensor tests (optics/test_correlating_sensor,
  optics/test_laws_correlating, optics/test_mutation_gaps_correlating_sensor);
- :func:`stubbed_sweep`, :func:`sweep_row`: ``closedloop sweep`` resumed in a folder whose
  ``rows/`` holds given row files, the sweep replaced by a stub (no simulation;
  test_sweep_superseded_review30, test_sweep_superseded_round47).

Test files import the functions (``from .conftest import small``); pytest's importlib mode
gives them the module pytest loaded, so there is one copy.
"""

import dataclasses

import pytest

from closedloop import presets
from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from closedloop.optics.actuator_dm import valid_actuators


@pytest.fixture(scope="module")
def tiny_actuator_loop() -> SimulationConfig:
    """table1 scaled down: one ground layer, 8 x 8 subapertures, 9 x 9 actuators, all modes."""
    return tiny_actuator_config()


def tiny_actuator_config() -> SimulationConfig:
    """The config of :func:`tiny_actuator_loop`, for files outside this folder
    (``from ..closedloop.conftest import tiny_actuator_config``)."""
    cfg = SimulationConfig(
        name="tiny-actuators",
        telescope=TelescopeConfig(diameter=4.0, n_pixels=32),
        layers=(LayerConfig(altitude=0.0, d_over_r0=16.0, wind_speed=10.0),),
        dms=(DMConfig(altitude=0.0, n_modes=10, kind="actuators"),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=8, noise=0.0, dm=0),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=0.5e-3, gain=0.5),
        field=FieldConfig(size=0.0, n_points=1),
        wavelength=500e-9, r0_wavelength=500e-9, seed=0)
    return cfg.replace(dms=(dataclasses.replace(cfg.dms[0],
                                                n_modes=valid_actuators(cfg, 0) - 1),))


def shrunk(config: SimulationConfig, modes: tuple[int, ...], *, n_pixels: int = 32,
           n_subapertures: int = 8, field_samples: int = 2, noise: float | None = None,
           kind: str = "shack_hartmann",
           field: FieldConfig | None = None) -> SimulationConfig:
    """``config``'s layout on a small pupil: the recipe the MCAO tests shrink presets with.

    Kept: the layers, the loop, the DM altitudes, and per WFS its altitude, field of view,
    DM and (``noise=None``) noise [arcsec]. Set: a 4 m pupil of ``n_pixels`` pixels, Zernike
    DMs of ``modes`` modes (one per DM), WFSs of ``kind`` with ``n_subapertures`` across and
    ``field_samples``, and the science ``field`` (default: a 3 x 3 grid over 60"); every
    other WFS setting is the default.
    """
    field = FieldConfig(size=60.0, n_points=3) if field is None else field
    dms = tuple(DMConfig(altitude=d.altitude, n_modes=m)
                for d, m in zip(config.dms, modes, strict=True))
    wfss = tuple(WFSConfig(altitude=w.altitude, field_of_view=w.field_of_view,
                           n_subapertures=n_subapertures,
                           noise=w.noise if noise is None else noise, dm=w.dm,
                           field_samples=field_samples, kind=kind) for w in config.wfss)
    return config.replace(telescope=TelescopeConfig(diameter=4.0, n_pixels=n_pixels), dms=dms,
                          wfss=wfss, field=field)


def with_values(cfg: SimulationConfig, section: str, index, **values) -> SimulationConfig:
    """``cfg`` with ``values`` set in its ``section`` (its item ``index`` if not None)."""
    d = cfg.to_dict()
    if index is None:
        d[section].update(values)
    else:
        d[section][index].update(values)
    return SimulationConfig.from_dict(d)


def small(name: str = "table1", **loop) -> SimulationConfig:
    """Preset ``name``'s layout made fast: 32 pupil pixels, 8 x 8 SH, 35 + 20 (+ 14) modes.

    :func:`shrunk` with its defaults, the preset's noise and loop; ``loop`` replaces loop
    fields (``gain=0.3``, ``delay=0.0``), validated as the config validates them
    (``loop.gain`` named in the error). Sizes: 32 pixels across 4 m (12.5 cm, under
    table1's ground r0 of 4 / 26 = 15 cm); 8 subapertures of 4 pixels (the rule asks 2);
    35 and 20 Zernikes (radial orders 7 and 5: complete orders, well under the 16 that 32
    pixels sample); a 3 x 3 science grid over 60" (table1's is 9 x 9 over 120"): off-axis
    directions, few of them.
    """
    c = presets.get(name)
    c = shrunk(c, (35, 20, 14)[:len(c.dms)])
    return c.replace(loop=LoopConfig(**{**vars(c.loop), **loop}))


def lag_only(*, gain: float = 0.5, delay: float = 1e-3,
             integration: float = 1e-3) -> SimulationConfig:
    """A loop whose only error is the servo lag: the budget's temporal term is its residual.

    Ideal sensor (no noise, no aliasing) and zonal "ideal" DM (no fitting error) on one
    ground layer of D/r0 = 20 (at 500 nm; science at 630 nm) blowing 1.3 pixels a frame,
    32 pixels across 2 m (81 m/s: under the 100 m/s wind rule, left26-twins; 4 m gave
    162.5 m/s, refused since; the loop is the same in pixels and frames); ``gain``,
    ``delay`` [s] and ``integration`` [s] set the servo (1 ms frames). The defaults
    (gain 0.5, one-frame delay) are test_budget_terms' loop.
    """
    n = 32
    dx = 2.0 / n
    return SimulationConfig(
        name="temporal",
        telescope=TelescopeConfig(diameter=2.0, n_pixels=n),
        layers=(LayerConfig(altitude=0.0, d_over_r0=20.0, wind_speed=1.3 * dx / 1e-3),),
        dms=(DMConfig(altitude=0.0, n_modes=20, kind="ideal"),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, kind="ideal", noise=0.0,
                        n_subapertures=8, field_samples=1),),
        loop=LoopConfig(time_step=1e-3, integration_time=integration, delay=delay,
                        gain=gain),
        field=FieldConfig(size=0.0, n_points=1), wavelength=630e-9, r0_wavelength=500e-9)


#: the mutation-gap loops' telescope diameter [m], r0 wavelength and science wavelength [m]
GAP_DIAMETER = 4.0
GAP_R0_WAVELENGTH = 500e-9
GAP_WAVELENGTH = 630e-9


def gap_config(name: str, layers, dms, wfss, *, n_points: int = 1,
               loop: LoopConfig | None = None, n_pixels: int = 32, zenith_angle: float = 0.0,
               obscuration: float = 0.0) -> SimulationConfig:
    """A small loop of the mutation-gap tests: a 4-m pupil, science on a 30" field.

    ``layers``: ``(altitude [m], D/r0, wind speed [m/s])`` per layer (other layer fields
    default); ``dms`` and ``wfss``: the configs as given (see :func:`gap_sensor`);
    ``n_points`` across the 30" science field; ``loop`` default ``LoopConfig()``; the
    telescope of ``n_pixels`` across :data:`GAP_DIAMETER`, at ``zenith_angle`` [deg] with
    ``obscuration``; science at :data:`GAP_WAVELENGTH`, r0 at :data:`GAP_R0_WAVELENGTH`.
    """
    return SimulationConfig(
        name=name,
        telescope=TelescopeConfig(diameter=GAP_DIAMETER, n_pixels=n_pixels,
                                  zenith_angle=zenith_angle, obscuration=obscuration),
        layers=tuple(LayerConfig(altitude=h, d_over_r0=s, wind_speed=v) for h, s, v in layers),
        dms=tuple(dms), wfss=tuple(wfss), loop=LoopConfig() if loop is None else loop,
        field=FieldConfig(size=30.0, n_points=n_points), wavelength=GAP_WAVELENGTH,
        r0_wavelength=GAP_R0_WAVELENGTH)


def gap_sensor(altitude: float, field: float, noise: float, dm: int,
               kind: str = "shack_hartmann") -> WFSConfig:
    """A mutation-gap sensor: 8 x 8 subapertures, 2 field samples across ``field`` [arcsec].

    ``altitude`` [m], ``noise`` [arcsec], driving DM ``dm``; ``kind`` a sensor kind.
    """
    return WFSConfig(altitude=altitude, field_of_view=field, n_subapertures=8, noise=noise,
                     field_samples=2, dm=dm, kind=kind)


def correlating_sensor(altitude: float, field: float, *, n_sub: int = 4,
                       field_samples: int = 1, dm: int = 0, kind: str = "correlating",
                       **options) -> WFSConfig:
    """A correlating-sensor test's WFS: ``n_sub`` x ``n_sub`` subapertures over ``field``.

    ``altitude`` [m], ``field`` [arcsec] sampled by ``field_samples`` across, driving DM
    ``dm``; ``kind`` (``"shack_hartmann"``: the geometric twin of the same grid);
    ``options``: other :class:`WFSConfig` fields (``noise``, ``image_formation``,
    ``signal``, ``contrast``).
    """
    return WFSConfig(altitude=altitude, field_of_view=field, kind=kind, n_subapertures=n_sub,
                     field_samples=field_samples, dm=dm, **options)


def correlating_config(name: str, layers, dms, wfss, *, diameter: float = 1.0,
                       n_pixels: int = 32, obscuration: float = 0.0,
                       wavelength: float = 630e-9,
                       r0_wavelength: float = 500e-9) -> SimulationConfig:
    """A correlating-sensor test's loop: frozen layers, 1-kHz frames, science on axis.

    ``layers``: ``(altitude [m], D/r0)`` per layer, frozen (no wind: a sensor's response
    to a known phase); ``dms``: ``(altitude [m], n_modes)`` per Zernike DM; ``wfss``: the
    sensors (:func:`correlating_sensor`); a telescope of ``diameter`` [m] sampled by
    ``n_pixels``, with ``obscuration``; 1 ms frames, exposure and delay, gain 0.5; science
    on axis at ``wavelength``, r0 at ``r0_wavelength`` [m].
    """
    return SimulationConfig(
        name=name,
        telescope=TelescopeConfig(diameter=diameter, n_pixels=n_pixels,
                                  obscuration=obscuration),
        layers=tuple(LayerConfig(altitude=h, d_over_r0=s, wind_speed=0.0) for h, s in layers),
        dms=tuple(DMConfig(altitude=h, n_modes=m) for h, m in dms), wfss=tuple(wfss),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=1e-3, gain=0.5),
        field=FieldConfig(size=0.0, n_points=1), wavelength=wavelength,
        r0_wavelength=r0_wavelength)


def turbulence_maps(model, seed: int) -> list:
    """Turbulence of every plane of ``model`` (its configured layers, one draw per seed)."""
    import numpy as np

    g = model.geometry
    atm = model.atmosphere(seed, 0.01)
    atm.reset()
    maps = [np.zeros((p.n, p.n)) for p in g.planes]
    for i, layer in enumerate(atm.layers):
        maps[g.layer_plane[i]] += layer.phase()
    return maps


def one_frame_budget(probe, maps: list):
    """The budget ``probe``'s terms for one frame whose turbulence is ``maps``."""
    import numpy as np

    class _Frozen:
        """A loop state whose turbulence is ``maps`` (the probe's only call into it)."""

        def turbulence(self, out):
            for v, m in zip(out, maps, strict=True):
                v[:] = m
            return out

    probe.rows = {k: [] for k in probe.rows}
    probe.step(0, _Frozen(), True)
    probe.frame_end(0, 1, 1)
    n_dir = len(probe.cam.directions)
    return probe.result(np.zeros((1, n_dir)), 0, 1.0, seed=0)


def sweep_row(key: str, seed: int = 0, predictor: str = "none") -> dict:
    """One ``closedloop sweep`` row file's content (an ok run of table1's "gain 0.3")."""
    return {"key": key, "override": "gain 0.3", "seed": seed, "predictor": predictor,
            "status": "ok", "strehl_peak_mean": 0.4, "corrected_fov_diameter_arcmin": 0.7}


@pytest.fixture
def stubbed_sweep(tmp_path, monkeypatch, capsys):
    """``run(rows, now, skipped=0)``: write ``rows`` (dicts with a ``key``) into a sweep
    folder's ``rows/``, replace ``closedloop.sweep.sweep`` by a stub returning ``now``, run
    ``closedloop sweep --quiet`` on a table1 grid of ``now``'s seeds (exit 0 asserted) and
    return the ``rows/`` folder and the lines printed."""
    import json
    import types

    import closedloop.sweep
    from closedloop.cli import main

    def run(rows: list[dict], now: list[dict], skipped: int = 0):
        out = tmp_path / "sdir"
        (out / "rows").mkdir(parents=True)
        for r in rows:
            (out / "rows" / f"{r['key']}.json").write_text(json.dumps(r))
        report = types.SimpleNamespace(n_specs=len(now), n_skipped=skipped,
                                       n_ok=len(now) - skipped, n_error=0, n_lost=0)
        monkeypatch.setattr(closedloop.sweep, "sweep", lambda *a, **k: (now, report))
        grid = tmp_path / "grid.toml"
        seeds = sorted({int(r["seed"]) for r in now})
        grid.write_text(f'preset = "table1"\nduration = 0.02\nseeds = {seeds}\n')
        assert main(["sweep", str(grid), "--out", str(out), "--quiet"]) == 0
        return out / "rows", capsys.readouterr().out.splitlines()

    return run
