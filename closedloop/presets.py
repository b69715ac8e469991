"""Named simulation configurations: the paper's Table 1, a larger MCAO case, and KAOS.

``table1`` is Table 1 of Stangalini et al. (LOST simulations): D = 4 m, zenith, 1 ms
time step, 1 ms integration, 0.5 ms loop delay, two Kolmogorov layers with D/r0 = 26
(ground) and 2 (upper), winds 7 and 70 m/s, two DMs conjugated to the layers ("perfect
matching"). What the table leaves open is set here, each with its reason:

==========================  ===========================  ========================================
parameter                   value                        why
==========================  ===========================  ========================================
D/r0 wavelength             500 nm                       the usual convention (site reports,
                                                         YAO ``dr0at05mic``, aotools)
science wavelength          630 nm                       DKIST's single-conjugate model quotes
                                                         its Strehl at 630 nm (A&A 2018,
                                                         aa33195-18, Table 1)
upper-layer altitude        10 km                        a 70 m/s wind is a jet-stream layer;
                                                         DKIST's model layers sit at 7.9 and
                                                         13.3 km, Big Bear's tropopause layer
                                                         at 8-12 km (Kellerer et al. 2012)
wind directions             0 deg (ground), 90 deg       Table 1 gives none; orthogonal winds
                            (upper)                      avoid a privileged field axis
pupil sampling              64 px across D (6.25 cm)     ground r0 15.4 cm (500 nm): 2.5 px
ground WFS                  60" field, 16x16 subaps      layer-oriented MFoV: widest field on
                                                         the ground (Ragazzoni et al. 2002);
                                                         a wide-field SH of ~1' (Kellerer 2012)
upper WFS                   20" field, 16x16 subaps      narrow field for the high layer
                                                         (Ragazzoni et al. 2002)
WFS noise                   0.005" per axis per subap    a few mas: correlating SH on
                                                         granulation (Loefdahl 2010)
ground DM modes             Z2-Z120 (radial order 14)    ~0.6 modes per slope pair of a 16x16
                                                         SH (well conditioned)
upper DM modes              Z2-Z66 (radial order 10)     over its 5 m sensed meta-pupil
integrator gain             0.5, no leak                 DKIST model's gain (aa33195-18)
science field               9x9 directions over 120"     the ~2' corrected field solar
                                                         telescopes aim at (paper, Sect. 1)
==========================  ===========================  ========================================

``mcao3`` has five layers (Big Bear-like: 60 % below 500 m, 35 % at 1-7 km, 5 % near the
tropopause; Kellerer et al. 2012) and three DMs at 0, 4 and 10 km: it shows that nothing
is hard-wired to two layers or two DMs. ``table1-wind`` is ``table1`` with the ground
layer at 21 m/s, the case where the temporal error is large enough for prediction to pay.

``table1-solar`` is ``table1`` sensed on granulation: both WFSs ``kind="correlating"``
(:class:`closedloop.optics.correlating_sensor.CorrelatingShackHartmann`, the linear
mode) with table1's fields (60" ground, 20" upper) and subapertures, 0.5" pixels, the
default photon budget (half of a 30 000 e- well per pixel per 1 ms frame, 2 e- read
noise: ``closedloop.optics.correlating.PhotonBudget``) and the default granulation
contrast at 500 nm (18 %), so the noise follows from photons and contrast instead of
table1's hand-set 0.005". Its loop delay is :data:`SOLAR_RTC_DELAY`, 1 ms from the end
of the exposure to the command (table1: 0.5 ms): a correlating SH must read the whole
subaperture images out and correlate them before reconstructing, and solar AO systems
run with a total latency of about one to two frames of a ~1-2 kHz loop (Rimmele &
Marino 2011, Living Rev. Sol. Phys. 8, 2, on the real-time control of solar AO). The
number is a documented choice of a fixed value for a DKIST/GREGOR-class correlating-SH
controller (readout ~0.5 ms plus correlation and reconstruction ~0.5 ms), not a
measurement on this machine; the latency study varies it.

``kaos`` is single-conjugate AO at a 0.7 m solar telescope, the kind of system whose log
the paper's Figures 1 and 5 analyse (KAOS at the VTT, Tenerife; the paper's log is not
public). It writes the shipped closed-loop log ``data/kaos_closedloop.npz``
(``data/make_data.py``) and runs the compression x prediction study (Figure 6):

==========================  ===========================  ========================================
parameter                   value                        why
==========================  ===========================  ========================================
aperture                    D = 0.70 m, unobstructed     the VTT's entrance aperture (paper,
                                                         Sect. 2.1; von der Luehe et al. 2003)
Shack-Hartmann              7 x 7 subapertures of 10 cm  the paper's 36 subapertures: 7 across
                                                         gives 37 with >= half their area lit
modes                       Z2-Z28 (27)                  the KAOS reconstruction (paper)
frame rate                  2 kHz, 1 frame exposure,     ~2 kHz (paper); a 1-frame
                            1 frame (0.5 ms) delay       computation/transfer delay, as in
                                                         ``telemetry.synthetic.kaos_like``
integrator gain             0.4664                       0 dB rejection bandwidth 130 Hz for
                                                         this timing (``modalinfo.servo.
                                                         gain_for_bandwidth``); KAOS-class loops
                                                         quote 100-130 Hz
seeing                      r0 = 7 cm at 500 nm          a moderate daytime r0 (D/r0 = 10), the
                            (D/r0 = 10), L0 = 20 m       value of the spectral KAOS-like log
layers                      70 % ground, 5 m/s; 30 % at  the split of ``kaos_like``; daytime
                            3 km, 10 m/s, orthogonal     profiles put most turbulence near the
                                                         ground and a weaker layer at a few km
                                                         (Kellerer et al. 2012)
WFS field                   10" (correlating SH)         a ~10" granulation subfield per
                                                         subaperture
WFS noise                   0.01" per axis per subap     a 10 cm subaperture on granulation:
                                                         twice table1's 0.005" (Loefdahl 2010:
                                                         the shift error grows as the
                                                         subaperture shrinks)
pupil sampling              56 px (1.25 cm, r0 / 5.6)    8 px per subaperture
science                     630 nm, 3x3 over 10"         the isoplanatic patch of a 3 km layer
                                                         at r0 = 7 cm is a few arcsec
==========================  ===========================  ========================================
"""

from __future__ import annotations

import dataclasses

from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)

__all__ = ["get", "names", "table1", "table1_wind", "table1_solar", "mcao3", "kaos",
           "SOLAR_RTC_DELAY", "dkist_scao", "dkist_scao_5cm"]

#: loop delay of ``table1-solar`` [s]: readout plus correlation and reconstruction of a
#: solar correlating-SH real-time controller (module docstring)
SOLAR_RTC_DELAY = 1.0e-3


def table1() -> SimulationConfig:
    """Return the paper's Table 1 with the documented defaults of the module docstring."""
    return SimulationConfig(
        name="table1",
        telescope=TelescopeConfig(diameter=4.0, obscuration=0.0, zenith_angle=0.0, n_pixels=64),
        layers=(
            LayerConfig(altitude=0.0, d_over_r0=26.0, wind_speed=7.0, wind_direction=0.0),
            LayerConfig(altitude=10_000.0, d_over_r0=2.0, wind_speed=70.0, wind_direction=90.0),
        ),
        dms=(
            DMConfig(altitude=0.0, n_modes=119),
            DMConfig(altitude=10_000.0, n_modes=65),
        ),
        wfss=(
            WFSConfig(altitude=0.0, field_of_view=60.0, n_subapertures=16, noise=0.005, dm=0),
            WFSConfig(altitude=10_000.0, field_of_view=20.0, n_subapertures=16, noise=0.005,
                      dm=1),
        ),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3, delay=0.5e-3, gain=0.5),
        field=FieldConfig(size=120.0, n_points=9),
        wavelength=630e-9,
        r0_wavelength=500e-9,
        seed=0,
    )


def mcao3() -> SimulationConfig:
    """Five layers, three DMs (0, 4, 10 km): the general case.

    The total turbulence is table1's ground layer, total D/r0 = 26 at 500 nm, split as
    the module docstring says (fractions of (D/r0)^(5/3), layers adding by the 3/5 law).
    """
    total = 26.0 ** (5 / 3)
    fractions = (0.45, 0.15, 0.2, 0.15, 0.05)
    altitudes = (0.0, 500.0, 4_000.0, 7_000.0, 12_000.0)
    winds = (7.0, 10.0, 20.0, 30.0, 70.0)
    directions = (0.0, 30.0, 60.0, 120.0, 90.0)
    layers = tuple(
        LayerConfig(altitude=h, d_over_r0=(f * total) ** 0.6, wind_speed=v, wind_direction=d)
        for f, h, v, d in zip(fractions, altitudes, winds, directions, strict=True)
    )
    dm_alts = (0.0, 4_000.0, 10_000.0)
    fields = (60.0, 30.0, 20.0)
    modes = (119, 65, 44)
    base = table1()
    return base.replace(
        name="mcao3",
        layers=layers,
        dms=tuple(DMConfig(altitude=h, n_modes=m) for h, m in zip(dm_alts, modes, strict=True)),
        wfss=tuple(WFSConfig(altitude=h, field_of_view=f, n_subapertures=16, noise=0.005, dm=i)
                   for i, (h, f) in enumerate(zip(dm_alts, fields, strict=True))),
    )


def table1_wind() -> SimulationConfig:
    """``table1`` with the ground layer at 21 m/s: a loop whose temporal error matters.

    Three times Table 1's ground wind (a strong daytime ground wind; the jet-stream
    layer stays at 70 m/s) raises the on-axis temporal error from ~0.02 to ~0.12 rad^2
    at 630 nm, so that prediction has something to remove (docs/CLOSEDLOOP.md).
    """
    base = table1()
    ground = dataclasses.replace(base.layers[0], wind_speed=21.0)
    return base.replace(name="table1-wind", layers=(ground, *base.layers[1:]))


def table1_solar() -> SimulationConfig:
    """``table1`` with correlating Shack-Hartmanns on granulation (module docstring)."""
    base = table1()
    wfss = tuple(dataclasses.replace(w, kind="correlating", noise=0.0) for w in base.wfss)
    loop = dataclasses.replace(base.loop, delay=SOLAR_RTC_DELAY)
    return base.replace(name="table1-solar", wfss=wfss, loop=loop)


#: integrator gain of ``kaos``: 130 Hz 0 dB rejection bandwidth at 2 kHz with a 1-frame
#: exposure and a 1-frame delay (``modalinfo.servo.gain_for_bandwidth``; a test checks it)
KAOS_GAIN = 0.4664
KAOS_BANDWIDTH = 130.0


def kaos() -> SimulationConfig:
    """Single-conjugate AO at a 0.7 m solar telescope (KAOS-like; module docstring)."""
    total = 10.0 ** (5 / 3)
    fractions = (0.7, 0.3)
    return SimulationConfig(
        name="kaos",
        telescope=TelescopeConfig(diameter=0.7, obscuration=0.0, zenith_angle=0.0,
                                  n_pixels=56),
        layers=tuple(
            LayerConfig(altitude=h, d_over_r0=(f * total) ** 0.6, wind_speed=v,
                        wind_direction=d, outer_scale=20.0)
            for f, h, v, d in zip(fractions, (0.0, 3_000.0), (5.0, 10.0), (0.0, 90.0),
                                  strict=True)),
        dms=(DMConfig(altitude=0.0, n_modes=27),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=10.0, n_subapertures=7, noise=0.01,
                        dm=0),),
        loop=LoopConfig(time_step=0.5e-3, integration_time=0.5e-3, delay=0.5e-3,
                        gain=KAOS_GAIN),
        field=FieldConfig(size=10.0, n_points=3),
        wavelength=630e-9,
        r0_wavelength=500e-9,
        seed=0,
    )


#: ``dkist-scao``'s published model (A&A 2018, aa33195-18, Table 1): Fried parameter at
#: 500 nm [m] of the nominal case and of the variant ``dkist-scao-5cm``
DKIST_R0 = 0.07
DKIST_R0_BAD = 0.05
#: its layers: altitudes [m] and fractions of the turbulence (weights of r0^(-5/3))
DKIST_ALTITUDES = (0.0, 7_852.0, 13_252.0)
DKIST_WEIGHTS = (0.942, 0.038, 0.02)
#: DM-space K-L modes controlled by ``dkist-scao`` (of the 1,584 valid actuators of 44 x 44;
#: docs/CLOSEDLOOP.md, "4-m single conjugate: dkist-scao")
DKIST_MODES = 1_200


def dkist_scao(r0: float = DKIST_R0) -> SimulationConfig:
    """DKIST's single-conjugate AO as the A&A 2018 model has it (aa33195-18, Table 1).

    Published (aa33195-18, Table 1; ``../shared/reference/solar-mcao-notes.md``):

    ==========================  ===========================  ====================================
    parameter                   value                        source
    ==========================  ===========================  ====================================
    aperture                    D = 4 m, unobstructed        Table 1 (DKIST is off-axis: no
                                                             central obscuration; Rimmele et al.
                                                             2020, Sol. Phys. 295, 172)
    Shack-Hartmann              43 x 43 subapertures         Table 1 (geometric SH: the model's)
    DM                          44 x 44 actuators            Table 1 (Fried geometry: 43 + 1)
    exposure, delay             2 ms, 0.5 ms                 Table 1 (500 Hz frames)
    integrator gain             0.5                          Table 1
    layers                      0, 7.852, 13.252 km with     Table 1
                                weights 0.942, 0.038, 0.02
    wind                        10 m/s (every layer)         Table 1
    outer scale                 L0 = 27 m                    Table 1
    r0 (500 nm)                 7 cm (``dkist-scao``),       Table 1 (SR 0.30 and 0.12 at
                                5 cm (``dkist-scao-5cm``)    630 nm)
    science wavelength          630 nm                       Table 1
    ==========================  ===========================  ====================================

    Left open by the paper, chosen here:

    ==========================  ===========================  ====================================
    parameter                   value                        why
    ==========================  ===========================  ====================================
    pupil sampling              172 px (2.33 cm, 4 px per    issue 29's model; r0 / 3 at 7 cm,
                                subaperture)                 2 px per actuator pitch (the
                                                             ``"actuators"`` kind's minimum)
    DM influence                Gaussian, coupling 0.35,     OOPAO's ``mechCoupling`` default (a
                                valid by illumination 0.05   continuous-facesheet piezo DM);
                                                             COMPASS/yao ``thresh`` rule
    controlled modes            1,200 DM-space K-L (of the   >= 1,000 (issue 29); measured SR
                                1,583 of 1,584 valid         0.329 / 0.333 / 0.331 at 1,000 /
                                actuators)                   1,200 / 1,500 modes: beyond 1,200
                                                             the high modes' aliasing and
                                                             temporal error eat the fitting gain
                                                             (docs/CLOSEDLOOP.md)
    WFS field                   on axis (0")                 the model's geometric SH on a point
                                                             (single conjugate)
    WFS noise                   0.01" per axis per subap     a 9.3 cm subaperture on granulation,
                                                             as ``kaos``'s 10 cm (Loefdahl 2010);
                                                             0.0006 rad^2 at 630 nm, it would
                                                             take ~0.07" to move the SR by 0.01
    wind directions             0, 90, 45 deg                none given; not along one axis
    science field               on axis                      one Strehl per r0 is published (the
                                                             direction of the SCAO guide region)
    ==========================  ===========================  ====================================

    The r0 = 5 cm case is the second preset name ``dkist-scao-5cm`` (``dkist_scao(0.05)``),
    the same model with every layer's ``D / r0`` scaled to the total ``4 / 0.05``: ask
    for it by name (``--preset dkist-scao-5cm``) rather than by editing three layers'
    ``d_over_r0`` in a TOML file (``closedloop config --preset dkist-scao-5cm`` writes it).
    ``r0`` [m at 500 nm] sets the total; the weights stay the published ones.
    """
    total = (4.0 / r0) ** (5 / 3)
    layers = tuple(
        LayerConfig(altitude=h, d_over_r0=(f * total) ** 0.6, wind_speed=10.0,
                    wind_direction=d, outer_scale=27.0)
        for f, h, d in zip(DKIST_WEIGHTS, DKIST_ALTITUDES, (0.0, 90.0, 45.0), strict=True))
    name = "dkist-scao" if r0 == DKIST_R0 else f"dkist-scao-{r0 * 100:g}cm"
    return SimulationConfig(
        name=name,
        telescope=TelescopeConfig(diameter=4.0, obscuration=0.0, zenith_angle=0.0,
                                  n_pixels=172),
        layers=layers,
        dms=(DMConfig(altitude=0.0, n_modes=DKIST_MODES, kind="actuators",
                      options={"n_actuators": 44}),),
        wfss=(WFSConfig(altitude=0.0, field_of_view=0.0, n_subapertures=43, noise=0.01,
                        field_samples=1, dm=0),),
        loop=LoopConfig(time_step=2e-3, integration_time=2e-3, delay=0.5e-3, gain=0.5),
        field=FieldConfig(size=0.0, n_points=1),
        wavelength=630e-9,
        r0_wavelength=500e-9,
        seed=0,
    )


def dkist_scao_5cm() -> SimulationConfig:
    """``dkist-scao`` at r0 = 5 cm (500 nm), the published model's bad-seeing case."""
    return dkist_scao(DKIST_R0_BAD)


_PRESETS = {"table1": table1, "table1-wind": table1_wind, "table1-solar": table1_solar,
            "mcao3": mcao3, "kaos": kaos, "dkist-scao": dkist_scao,
            "dkist-scao-5cm": dkist_scao_5cm}


def names() -> list[str]:
    """Names of the presets."""
    return list(_PRESETS)


def get(name: str) -> SimulationConfig:
    """Return the preset ``name`` (see :func:`names`) as a :class:`SimulationConfig`."""
    if name not in _PRESETS:
        raise ValueError(f"`name` must be one of {', '.join(_PRESETS)}; got {name!r}.")
    return _PRESETS[name]()
