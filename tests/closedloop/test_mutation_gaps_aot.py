"""closedloop.aot: the export's cards, telescope, correctors and refusals, read back by aotpy.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/aot.py"). References, from
outside the module under test:

- ``aotpy.AOSystem.read_from_file`` (an independent reader of the FITS file) and
  astropy's header reader;
- the export's documented layout (``closedloop/aot.py``'s docstring): telescope
  ``"telescope"``, elevation ``90 - zenith_angle``, central obstruction ``obscuration x
  D`` [m] (none without one); the source ``"sun"``, natural, ``extended = "sun"`` in
  its ``MI_GEOM`` entry; each corrector's
  ``MI_GEOM`` extras: the DM's disc ``D + 2 h sec z tan(F / 2)`` [m], its line-of-sight
  altitude ``h sec z``, its plane grid and pixel ``D / n_pixels``; each loop's
  coefficient card ``MI_QUANT`` (``residual``, ``pol``); an open loop's ``closed`` false;
  the ``MI_CLOOP`` card naming the run's seed, predictor, ``r0_wavelength`` and every
  loop the file holds;
- the run's own inputs (config, seed, predictor name) as the user gave them;
- the project's rule for bad input: the message names the argument, the rule, the value.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

aotpy = pytest.importorskip("aotpy")

from closedloop import ORACLE, LoopModel, simulate  # noqa: E402
from closedloop.aot import (  # noqa: E402
    aot_wind_direction,
    build_aot_system,
    export_aot,
    wind_direction_from_aot,
)
from closedloop.config import (  # noqa: E402
    ARCSEC,
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from modalinfo.io.aot_system import geometry_of  # noqa: E402

D, OBSC, ZENITH = 2.0, 0.2, 30.0


def _config(*, closed: bool) -> SimulationConfig:
    # a 2 m telescope at 30 deg from the zenith (obscured in the open-loop run, not in the
    # closed one), a ground and a 4-km DM (so a disc larger than the pupil and a line of
    # sight longer than the altitude)
    return SimulationConfig(
        name="tiny",
        telescope=TelescopeConfig(diameter=D, n_pixels=16,
                                  obscuration=0.0 if closed else OBSC, zenith_angle=ZENITH),
        layers=(LayerConfig(altitude=0.0, d_over_r0=3.0, wind_speed=5.0),
                LayerConfig(altitude=4000.0, d_over_r0=2.0, wind_speed=10.0)),
        dms=(DMConfig(altitude=0.0, n_modes=9), DMConfig(altitude=4000.0, n_modes=5)),
        wfss=(WFSConfig(altitude=0.0, field_of_view=20.0, n_subapertures=4, noise=0.01,
                        field_samples=1, dm=0),
              WFSConfig(altitude=4000.0, field_of_view=20.0, n_subapertures=4, noise=0.01,
                        field_samples=1, dm=1)),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=1e-3, gain=0.4,
                        closed=closed),
        field=FieldConfig(size=0.0, n_points=1), wavelength=630e-9, r0_wavelength=500e-9)


@pytest.fixture(scope="module", params=[False, True], ids=["open", "oracle"])
def exported(request, tmp_path_factory):
    closed = request.param
    cfg = _config(closed=closed)
    model = LoopModel(cfg)
    run = simulate(cfg, 0.005, seed=11, model=model, progress=False,
                   predictor=ORACLE if closed else None)
    path = export_aot(run, tmp_path_factory.mktemp("aot") / "run.fits", model=model)
    return cfg, model, run, aotpy.AOSystem.read_from_file(path)


def _card(system, key):
    (value,) = [m.value for m in system.metadata if m.key == key]
    return value


def test_telescope_is_elevated_and_obscured_as_configured(exported):
    cfg, _, _, system = exported
    tel = system.main_telescope
    assert tel.elevation == pytest.approx(90.0 - ZENITH, abs=1e-12)
    if cfg.telescope.obscuration:
        assert tel.obstruction_diameter == pytest.approx(OBSC * D, rel=1e-12)  # [m], not 0.2
        assert tel.inscribed_diameter is None
    else:       # no obstruction: none written, and the pupil's inscribed circle is D
        assert tel.obstruction_diameter is None and tel.inscribed_diameter == D
    assert tel.enclosing_diameter == D
    assert tel.uid == "telescope"
    # the sun: a natural source (AOT has no extended-source type), said so in MI_GEOM
    (src,) = system.sources
    assert isinstance(src, aotpy.NaturalGuideStar) and src.uid == "sun"
    assert geometry_of(system)["sources"]["sun"]["extra"] == {
        "extended": "sun", "note": "AOT has no extended-source type"}
    assert system.name == "closedloop tiny"
    (atm,) = system.atmosphere_params          # the module docstring's uid
    assert atm.uid == "atmosphere"


def test_loops_say_open_or_closed_and_what_their_coefficients_are(exported):
    cfg, _, run, system = exported
    quant = {}
    for lp in system.loops:
        assert lp.closed is cfg.loop.closed
        if lp.modal_coefficients is not None:
            (card,) = [m.value for m in lp.modal_coefficients.metadata if m.key == "MI_QUANT"]
            quant[lp.uid] = card
            # residual and POL alike: modal phase in rad at r0_wavelength (docstring)
            assert lp.modal_coefficients.unit == "rad", lp.uid
    assert quant == {"dm0": "residual", "dm1": "residual", "dm0.pol": "pol", "dm1.pol": "pol"}


def test_correctors_describe_their_disc_and_line_of_sight(exported):
    cfg, model, _, system = exported
    sec = 1.0 / math.cos(math.radians(ZENITH))
    geom = geometry_of(system)["correctors"]
    dx = D / cfg.telescope.n_pixels
    field = max(cfg.field.size, max(w.field_of_view for w in cfg.wfss))
    for i, d in enumerate(cfg.dms):
        extra = geom[f"dm{i}"]["extra"]
        los = d.altitude * sec
        assert extra["line_of_sight_altitude"] == pytest.approx(los, rel=1e-12)
        assert extra["disc_diameter"] == pytest.approx(
            D + 2.0 * los * math.tan(field / 2.0 * ARCSEC), rel=1e-12)
        assert extra["pixel_scale"] == pytest.approx(dx, rel=1e-12)
        mask = np.asarray(system.wavefront_correctors[i].pupil_mask.data)
        assert extra["plane_pixels"] == mask.shape[0] == mask.shape[1]
        # the plane grid holds the disc: at least its diameter in pixels
        assert extra["plane_pixels"] >= extra["disc_diameter"] / dx
        assert geom[f"dm{i}"]["altitude"] == d.altitude
        # what an "actuator" is (the module docstring: modal, one actuator per mode)
        assert extra["model"].startswith("modal: each actuator is one mode")
        # a binary integer mask: 1 on the disc's pixels, 0 elsewhere
        assert mask.dtype.kind in "iu" and set(np.unique(mask)) == {0, 1}
        np.testing.assert_array_equal(np.flatnonzero(mask), model.dms[i].pixels)


def test_the_closedloop_card_names_the_run(exported):
    cfg, _, run, system = exported
    card = json.loads(_card(system, "MI_CLOOP"))
    assert card["written_by"] == "closedloop"
    assert card["seed"] == 11
    assert card["version"] == run.version and run.version      # the writing package's
    assert card["predictor"] == ("oracle" if cfg.loop.closed else "none")
    assert card["r0_wavelength"] == cfg.r0_wavelength
    assert sorted(card["loops"]) == sorted(lp.uid for lp in system.loops)
    for uid, text in card["loops"].items():
        log = "dm" + uid[2] + (".pol" if uid.endswith(".pol") else
                               ".residual" if "." not in uid else "")
        assert log in text, (uid, text)
    assert "(270 - a) mod 360" in card["wind_direction"]
    # the conventions the module docstring states: phase in rad at r0_wavelength, slopes
    # in rad/m, altitudes in m above the telescope, the Strehl ratio over the field after
    # loop closure
    assert "rad at r0_wavelength" in card["units"] and "rad/m" in card["units"]
    assert "m above the telescope" in card["altitudes"]
    assert "field" in card["strehl_ratio"] and "after loop closure" in card["strehl_ratio"]
    assert card["time_filter"].startswith("integrator c_k = (1 - leak) c_{k-1} + gain m_k")
    assert ("'oracle'" in card["time_filter"]) is cfg.loop.closed
    # a run without a predictor names none (the docstring: only a predictor is named)
    assert ("predictor" in card["time_filter"]) is (run.predictor != "none")
    if run.predictor == "none":     # the docstring's integrator, nothing more
        assert card["time_filter"] == "integrator c_k = (1 - leak) c_{k-1} + gain m_k"
    assert card["reconstructor"].startswith("global MAP")


def test_the_strehl_cards_are_the_runs(exported):
    cfg, _, run, system = exported
    # a FITS header card holds a value in 20 characters (FITS standard 4.2.4; astropy
    # shortens a float's repr to fit): a small SR written with an exponent keeps 15
    # significant digits ("1.23456789012345E-05"), a relative rounding of at most 5e-15, so
    # the card equals the run to 1e-14 relative, not always bit for bit (round 38 PART a:
    # differed in the last digits on one CPU for the open-loop run)
    assert system.strehl_ratio == pytest.approx(run.summary()["strehl_field_mean"],
                                                rel=1e-14, abs=0)
    assert system.strehl_wavelength == cfg.wavelength


def test_build_without_a_model_rebuilds_the_same_system(exported):
    cfg, model, run, _ = exported
    a = build_aot_system(run, model)
    b = build_aot_system(run)
    assert a.strehl_wavelength == b.strehl_wavelength == cfg.wavelength
    for la, lb in zip(a.loops, b.loops, strict=True):
        assert la.uid == lb.uid
        if la.measurements_to_modes is not None:
            np.testing.assert_array_equal(la.measurements_to_modes.data,
                                          lb.measurements_to_modes.data)


@pytest.mark.parametrize("bad", [np.nan, [1.0, np.inf]])
def test_wind_refusals_name_the_argument_and_the_value(bad):
    with pytest.raises(ValueError) as exc:
        aot_wind_direction(bad)
    assert str(exc.value) == f"`direction` must be finite [deg]; got {bad!r}."
    with pytest.raises(ValueError) as exc:
        wind_direction_from_aot(bad)
    assert str(exc.value) == f"`aot_direction` must be finite [deg]; got {bad!r}."


def test_an_existing_file_is_refused_before_any_work(exported, tmp_path):
    _, _, run, _ = exported
    path = tmp_path / "there.fits"
    path.write_bytes(b"user data")
    with pytest.raises(FileExistsError) as exc:
        export_aot(run, path, model=object())      # not a model: no work is done first
    assert str(exc.value) == f"'{path}' exists; pass overwrite=True to replace it"
    assert path.read_bytes() == b"user data"


def test_a_result_without_measurements_exports_sensors_without_them(exported, tmp_path):
    # a result recorded without measurements (``measurements=[]``, as files written
    # before they were recorded): every sensor is written, with no measurements image
    cfg, model, run, _ = exported
    bare = dataclasses.replace(run, measurements=[])
    system = aotpy.AOSystem.read_from_file(export_aot(bare, tmp_path / "bare.fits",
                                                      model=model))
    assert [s.uid for s in system.wavefront_sensors] == ["wfs0", "wfs1"]
    assert all(s.measurements is None for s in system.wavefront_sensors)


def test_measurements_of_the_wrong_shape_are_refused(exported):
    # the message names the dataset, its shape and the expected (frames, measurements)
    _, model, run, _ = exported
    (t, n) = run.measurements[0].shape
    bad = dataclasses.replace(run, measurements=[m[:, :-1] for m in run.measurements])
    with pytest.raises(ValueError) as exc:
        build_aot_system(bad, model)
    assert str(exc.value) == (f"result.measurements[0] has shape {(t, n - 1)}; expected "
                              f"{(t, n)}.")


def test_a_zonal_mirror_is_written_without_its_dense_identities(tmp_path):
    # an ideal sensor driving a zonal ("ideal") DM: its "actuators" are the disc's pixels,
    # the modes-to-commands and measurements-to-modes maps are identities, which are not
    # written (the module docstring: a dense pixels x pixels image; the MI_CLOOP card
    # says the identity is meant); the commands are written, one per disc pixel
    cfg = SimulationConfig(
        name="zonal",
        telescope=TelescopeConfig(diameter=D, n_pixels=8),
        layers=(LayerConfig(altitude=0.0, d_over_r0=3.0, wind_speed=5.0),),
        dms=(DMConfig(altitude=0.0, kind="ideal"),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=4.0, kind="ideal", field_samples=1),),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=1e-3, gain=0.4),
        field=FieldConfig(size=0.0, n_points=1))
    model = LoopModel(cfg)
    run = simulate(cfg, 0.003, seed=3, model=model, progress=False)
    system = aotpy.AOSystem.read_from_file(export_aot(run, tmp_path / "z.fits", model=model))
    (lp,) = [lp for lp in system.loops if lp.uid == "dm0"]
    assert lp.modes_to_commands is None and lp.measurements_to_modes is None
    assert lp.modes is None
    n_disc = model.dms[0].pixels.size
    assert np.asarray(lp.commands.data).shape == (run.times.size, n_disc)
    (dm,) = system.wavefront_correctors
    assert dm.n_valid_actuators == n_disc
    card = json.loads(_card(system, "MI_CLOOP"))
    assert "the identity, an ideal sensor on a zonal DM" in card["reconstructor"]
    assert geometry_of(system)["correctors"]["dm0"]["extra"]["modes"] == "pixels"


def test_a_model_of_another_config_is_refused_with_the_whole_message(exported):
    cfg, _, run, _ = exported
    other = LoopModel(_config(closed=not cfg.loop.closed))
    with pytest.raises(ValueError) as exc:
        build_aot_system(run, other)
    assert str(exc.value) == "`model` was built for another config than the result's."


@pytest.mark.parametrize("provenance, who", [
    (None, "an older version of the code (it recorded no source in its results)"),
    ({"git": "4c25775f", "source_sha256": "0" * 64}, "another version of the code (git 4c25775f)"),
])
def test_a_result_of_other_code_is_named_when_its_shapes_differ(exported, provenance, who):
    """Round 47 PART b V12 / W12: ``closedloop export`` of a result written by 351d5180
    (2026-11-29) said only "result.measurements[1] has shape (20, 240); expected (20, 400)":
    the same TOML gives today's 10-km Shack-Hartmann 200 valid subapertures (2e799ca8's
    field rule), 120 then. Reference: the result's own provenance (the source SHA-256 and
    git revision of the code that wrote it, or none for files written before results kept
    one) against this code's ``provenance.code_record()``."""
    _, model, run, _ = exported
    (t, n) = run.measurements[0].shape
    bad = dataclasses.replace(run, measurements=[m[:, :-1] for m in run.measurements],
                              provenance=provenance)
    with pytest.raises(ValueError) as exc:
        build_aot_system(bad, model)
    assert str(exc.value) == (
        f"result.measurements[0] has shape {(t, n - 1)}; expected {(t, n)}: the result was "
        f"written by {who}, which built its config differently; export it with that "
        "version, or run the config again with this one.")
