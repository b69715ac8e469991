"""Named simulation configurations: the paper's Table 1, larger MCAO cases, KAOS, DKIST and EST.

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

``est-mcao`` is the European Solar Telescope's multi-conjugate AO as published, where the
EST papers give a number, and a documented choice where they do not (the Montilla et al.
EST MCAO papers were not available here: "not found" below means no public figure was
found in this project's sources). ``est-mcao-solar`` is the same system sensed on
granulation: every WFS ``kind="correlating"`` (the default photon budget and contrast,
as ``table1-solar``) and the loop delay :data:`SOLAR_RTC_DELAY` (1 ms: readout 0.5 ms plus
correlation and reconstruction, the fixed value Figure 7 runs ``table1-solar`` with; its
latency study moves it with the RTC's speed):

==========================  ===========================  ========================================
parameter                   value                        why
==========================  ===========================  ========================================
aperture                    D = 4.2 m, unobstructed      EST's 4.2 m primary (IDOM; Sanquirce et
                                                         al. 2022, SPIE 12182); the on-axis
                                                         Gregorian's obscuration: not found
corrected field             60" circle; science on 7x7   "diffraction limited over a circular
                            points over 60" (10" steps)  FOV of 60 arcsec" (EST status paper,
                                                         Quintero Noda, Collados et al.)
DMs                         5, of actuators (Gaussian,   "the EST design includes 5 DMs" (EST
                            coupling 0.35), K-L modes    project, MCAO test-bench news 2021);
                                                         the adaptive secondary corrects the
                                                         ground layer (EST status paper)
DM altitudes                0 (adaptive secondary),      heights not found: DMs at the profile's
                            2.5, 5, 9, 14 km             free-atmosphere layers ("perfect
                                                         matching" as table1), the strongest
                                                         (2.5 km) where La Palma's profile peaks
ground WFS                  45 x 45 subapertures         9.3 cm: solar high-order SHs use 8-10 cm
                            (9.3 cm), 60" field          (GREGOR 92 mm; issue 29); layer-oriented
                                                         MFoV over the corrected field
                                                         (Ragazzoni et al. 2002; Kellerer 2012)
altitude WFSs               60" field, subapertures of   not found: the high layers are weaker,
                            2x the ground pitch (18.7    and EST's MCAO bench has fewer actuators
                            cm) over their 60" meta-     on its altitude DMs (2 x 468) than on its
                            pupil: 26/30/37/44 across    pupil DM (820; IAC, SOLARNET 2021)
actuators                   WFS's subapertures + 1       Fried geometry (``"actuators"`` kind);
                            across each disc: 1,740 /    a 60" meta-pupil at 14 km is 8.3 m
                            609 / 801 / 1,200 / 1,665
                            valid
controlled modes            0.9 per valid subaperture:   ~1,500 modes from ~3,000 slopes per WFS
                            1,431 / 478 / 636 / 968 /    (issue 29, the size peers control)
                            1,368
pupil sampling              180 px (4 per subaperture)   table1's 4 px per subaperture
seeing                      r0 = 7 cm at 500 nm (D/r0 =  DKIST's published 4-m model (A&A 2018,
                            60), L0 = 27 m every layer   aa33195-18), a moderate daytime r0
daytime profile (share of   0 m 45 %, 200 m 10 %,        Big Bear (Kellerer et al. 2012): 55-65 %
(D/r0)^(5/3))               1 km 15 %, 2.5 km 12 %,      below 500 m (here 55 %), 30-40 % at
                            5 km 8 %, 9 km 5 %, 14 km    1-7 km (35 %), ~5 % at the tropopause;
                            5 %                          La Palma: three layers within 1.5 km
                                                         (S-DIMM+, Scharmer & van Werkhoven
                                                         2010), the free-atmosphere peak at
                                                         2.5 km (Garcia-Lorenzo & Fuensalida
                                                         2011, Fig. 6), most turbulence near
                                                         the ground by day (Townson et al. 2015)
winds                       Bufton's profile at each     Bufton (1973) as Hardy (1998) gives it:
                            height: 5.7 ... 34.8 m/s     5 + 30 exp(-((h - 9.4 km)/4.8 km)^2);
                            (9 km); directions 0-180     directions spread (none published)
                            deg in 30 deg steps
loop                        1 kHz, 1 ms exposure,        table1's timing (paper's Table 1);
                            0.5 ms delay, gain 0.5       gain of DKIST's model
joint reconstructor         the MAP (``"map"``), with    Fusco et al. (2001)'s minimum-variance
                            pseudo-open-loop control     estimator; POLC as Ellerbroek & Vogel
                            (table1: truncated, plain    (2003) and Gilles (2005) run it in
                            integrator)                  closed loop (docs/CLOSEDLOOP.md, "EST
                                                         MCAO with the true MAP")
reconstructor model error   0.01 (table1: 0.3)           measured: the slopes the mirrors'
                                                         modes leave unexplained are 0.2-1.7 %
                                                         of the all-layer subaperture tilt
                                                         variance the setting scales (co-added
                                                         60"); the MAP's N is their variance,
                                                         so a value inside that range; the
                                                         best of 0.003-0.3 in closed loop
WFS noise (geometric SH)    0.01" per axis per subap     kaos's 10 cm subaperture value
                                                         (Loefdahl 2010)
science                     630 nm                       as every preset (DKIST's model)
==========================  ===========================  ========================================

The full size (five WFSs of 19 field samples, ~4,900 modes from ~10,800 slopes) needs
~6.5 GiB at its peak by ``closedloop.resources.estimate`` (the mirrors' shapes and the
dense reconstructor; the WFS operators are assembled one plane at a time); its set-up
measured 4.9 GiB and 216 s of CPU (``benchmarks/RESULTS.md``).
:func:`est_mcao_variant` builds the same system at a coarser resolution (its
``ground_subapertures``; every count follows from it by the rules of the table): the
runs of docs/CLOSEDLOOP.md ("EST MCAO") use :data:`EST_REDUCED_SUBAPERTURES` = 16
(``est-mcao@16``: 64 pixels, 26 cm ground subapertures, 181 / 57 / 86 / 119 / 181 modes).
"""

from __future__ import annotations

import dataclasses
import math

from closedloop.config import (
    DMConfig,
    FieldConfig,
    LayerConfig,
    LoopConfig,
    SimulationConfig,
    TelescopeConfig,
    WFSConfig,
)
from modalinfo.common.validation import check_int, check_real

__all__ = ["get", "names", "table1", "table1_wind", "table1_solar", "mcao3", "kaos",
           "SOLAR_RTC_DELAY", "dkist_scao", "dkist_scao_5cm", "est_mcao", "est_mcao_solar",
           "est_mcao_variant", "bufton_wind"]

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


# ------------------------------------------------------------------ EST MCAO (issue 29)
#: EST aperture [m]: the 4.2 m primary (EST project; IDOM, "European Solar Telescope",
#: and Sanquirce et al. 2022, Proc. SPIE 12182, 121821H)
EST_DIAMETER = 4.2
#: circular corrected field [arcsec] of EST's MCAO (Quintero Noda, Collados et al., "Overview
#: of the status of the European Solar Telescope": diffraction limited "over a circular FOV
#: of 60 arcsec")
EST_FIELD = 60.0
#: subapertures across the pupil of the ground (adaptive secondary's) WFS: 9.3 cm, within
#: the 8-10 cm of solar high-order SHs (GREGOR's 92 mm; issue 29)
EST_SUBAPERTURES = 45
#: the altitude WFSs' subaperture pitch as a multiple of the ground's (module docstring)
EST_ALTITUDE_PITCH = 2.0
#: ground subapertures of the reduced-resolution runs reported in docs/CLOSEDLOOP.md
#: ("EST MCAO"): table1's 16 across (26 cm), 64 pupil pixels
EST_REDUCED_SUBAPERTURES = 16
#: fewest ground subapertures of :func:`est_mcao_variant`: 4 pixels each, and the pupil
#: pixel no larger than r0 (the config's rule): ceil(D / r0 / 4)
EST_MIN_SUBAPERTURES = 15
#: most ground subapertures of :func:`est_mcao_variant`: ten times the published 45 (4.7 mm
#: subapertures, 1,800 pupil pixels): beyond it the config's own checks (actuator masks on
#: grids of the DM's size) allocate terabytes instead of answering
EST_MAX_SUBAPERTURES = 10 * EST_SUBAPERTURES
#: total r0 at 500 nm [m]: DKIST's published model (A&A 2018, aa33195-18), a moderate
#: daytime r0 at the Canary Islands sites
EST_R0 = 0.07
#: outer scale [m] of every layer (the same DKIST model)
EST_OUTER_SCALE = 27.0
#: daytime profile: (altitude [m], share of the turbulence (D/r0)^(5/3)); module docstring
EST_PROFILE = ((0.0, 0.45), (200.0, 0.10), (1_000.0, 0.15), (2_500.0, 0.12),
               (5_000.0, 0.08), (9_000.0, 0.05), (14_000.0, 0.05))
#: wind directions [deg] of the layers (none published: spread over half a turn so that
#: no field axis is privileged, as table1's orthogonal winds)
EST_WIND_DIRECTIONS = (0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0)
#: conjugation heights [m] of EST's five DMs: the adaptive secondary at the ground and
#: four DMs at the profile's free-atmosphere layers (module docstring)
EST_DM_ALTITUDES = (0.0, 2_500.0, 5_000.0, 9_000.0, 14_000.0)
#: controlled K-L modes per valid subaperture of a DM's WFS (0.45 per slope: about the
#: ~1,500 modes from ~3,000 slopes of issue 29; table1 has 0.58 per subaperture)
EST_MODES_PER_SUBAPERTURE = 0.9
#: geometric SH noise [arcsec RMS per axis per subaperture]: kaos's value for a 10 cm
#: subaperture on granulation (Loefdahl 2010)
EST_SH_NOISE = 0.01
#: ``loop.model_error`` of the EST presets: the joint MAP reconstructor's model error as a
#: share of a subaperture's all-layer turbulent tilt variance. Measured on est-mcao@16
#: (docs/CLOSEDLOOP.md, "the budget ladder"): the slopes the mirrors' modes leave
#: unexplained are 0.2-1.7 % of it (60" co-adding averages the high layers out). With
#: the true MAP (:data:`EST_RECONSTRUCTOR`) the model error is a noise covariance the
#: estimator weighs by (Fusco et al. 2001), not a cut: its value is the measured share,
#: 0.01 inside 0.002-0.017 (the ground WFS, with most of the turbulence, 0.017); in
#: closed loop the best of 0.003 / 0.01 / 0.03 / 0.1 / 0.3 (docs/CLOSEDLOOP.md, "EST
#: MCAO with the true MAP"). The truncated form needed 0.03, above every share (at 0.3 it
#: keeps 97 of 624 modes).
EST_MODEL_ERROR = 0.01
#: ``loop.reconstructor`` of the EST presets: the true MAP, run with pseudo-open-loop
#: control (``closedloop.control.controller``); with five mirrors the truncated form
#: keeps a third of the modes (230 of 624 at ``model_error`` 0.03)
EST_RECONSTRUCTOR = "map"


def bufton_wind(altitude: float) -> float:
    """Bufton (1973)'s wind speed [m/s] at ``altitude`` [m] (a 35 m/s jet near 9.4 km).

    ``5 + 30 exp(-((h - 9.4 km) / 4.8 km)^2)``, the model Hardy (1998, *Adaptive Optics
    for Astronomical Telescopes*, Ch. 3) gives for AO design.
    """
    return 5.0 + 30.0 * math.exp(-(((altitude - 9_400.0) / 4_800.0) ** 2))


def est_mcao_variant(ground_subapertures: int = EST_SUBAPERTURES, *, solar: bool = False,
                     altitude_pitch: float = EST_ALTITUDE_PITCH,
                     name: str | None = None) -> SimulationConfig:
    """EST's MCAO at a given resolution: ``est-mcao`` (or ``-solar``) with its counts scaled.

    Parameters
    ----------
    ground_subapertures : int
        Subapertures across the pupil of the ground WFS (the published design: 45). The
        pupil has 4 pixels per ground subaperture; each altitude WFS has subapertures of
        :data:`EST_ALTITUDE_PITCH` times the ground pitch across its 60" meta-pupil; each
        DM has its WFS's ``n_subapertures + 1`` actuators across (Fried geometry) and
        :data:`EST_MODES_PER_SUBAPERTURE` K-L modes per valid subaperture (``pi/4 n^2``).
        :data:`EST_REDUCED_SUBAPERTURES` (16) gives the runs of docs/CLOSEDLOOP.md: the
        same telescope, profile, field, loop and noise, with 2.8x coarser sampling.
    solar : bool
        Correlating Shack-Hartmanns and the solar delay (``est-mcao-solar``).
    altitude_pitch : float
        Subaperture pitch of the altitude WFSs in ground pitches (>= 1; the design choice
        the docs sweep).
    name : str, optional
        The config's name; default ``est-mcao[-solar]``, with ``@<n>`` when
        ``ground_subapertures`` is not 45.

    Returns
    -------
    SimulationConfig
    """
    # validation.check_int / check_real (the one copy): a NumPy integer or a 0-d array is
    # its number (np.int64(16) was refused as "must be an int": audit 9); bool, str refused
    n_g = check_int(ground_subapertures, "ground_subapertures")
    if n_g < EST_MIN_SUBAPERTURES:
        raise ValueError(f"`ground_subapertures` must be an int >= {EST_MIN_SUBAPERTURES} (4 "
                         f"pixels each, and a pixel no larger than r0 = {EST_R0 * 100:g} cm); "
                         f"got {ground_subapertures!r}.")
    if n_g > EST_MAX_SUBAPERTURES:
        raise ValueError(f"`ground_subapertures` must be <= {EST_MAX_SUBAPERTURES} (ten times "
                         f"the published {EST_SUBAPERTURES}: the pupil grid of 4 pixels per "
                         "subaperture and the actuator masks the config checks grow as its "
                         f"square); got {ground_subapertures!r}.")
    altitude_pitch = check_real(altitude_pitch, "altitude_pitch")
    if not 1.0 <= altitude_pitch <= 4.0:
        raise ValueError(f"`altitude_pitch` must be a number in [1, 4] (ground pitches); got "
                         f"{altitude_pitch!r}.")
    if name is None:
        name = "est-mcao" + ("-solar" if solar else "") + (
            "" if n_g == EST_SUBAPERTURES else f"@{n_g}")
    d = EST_DIAMETER
    total = (d / EST_R0) ** (5 / 3)
    layers = tuple(
        LayerConfig(altitude=h, d_over_r0=(f * total) ** 0.6, wind_speed=bufton_wind(h),
                    wind_direction=w, outer_scale=EST_OUTER_SCALE)
        for (h, f), w in zip(EST_PROFILE, EST_WIND_DIRECTIONS, strict=True))
    pitch = d / n_g
    half_field = math.radians(EST_FIELD / 2 / 3600.0)
    subaps = [n_g if h == 0 else
              max(4, round((d + 2 * h * math.tan(half_field)) / (altitude_pitch * pitch)))
              for h in EST_DM_ALTITUDES]
    modes = [round(EST_MODES_PER_SUBAPERTURE * math.pi / 4 * n * n) for n in subaps]
    kind, noise = ("correlating", 0.0) if solar else ("shack_hartmann", EST_SH_NOISE)
    return SimulationConfig(
        name=name,
        telescope=TelescopeConfig(diameter=d, obscuration=0.0, zenith_angle=0.0,
                                  n_pixels=4 * n_g),
        layers=layers,
        dms=tuple(DMConfig(altitude=h, n_modes=m, kind="actuators")
                  for h, m in zip(EST_DM_ALTITUDES, modes, strict=True)),
        wfss=tuple(WFSConfig(altitude=h, field_of_view=EST_FIELD, n_subapertures=n,
                             noise=noise, kind=kind, dm=i)
                   for i, (h, n) in enumerate(zip(EST_DM_ALTITUDES, subaps, strict=True))),
        loop=LoopConfig(time_step=1e-3, integration_time=1e-3,
                        delay=SOLAR_RTC_DELAY if solar else 0.5e-3, gain=0.5,
                        model_error=EST_MODEL_ERROR, reconstructor=EST_RECONSTRUCTOR),
        field=FieldConfig(size=EST_FIELD, n_points=7),
        wavelength=630e-9,
        r0_wavelength=500e-9,
        seed=0,
    )


def est_mcao() -> SimulationConfig:
    """EST's MCAO as published, geometric Shack-Hartmanns (module docstring, "EST")."""
    return est_mcao_variant()


def est_mcao_solar() -> SimulationConfig:
    """``est-mcao`` sensed on granulation, with the solar delay (module docstring, "EST")."""
    return est_mcao_variant(solar=True)


_PRESETS = {"table1": table1, "table1-wind": table1_wind, "table1-solar": table1_solar,
            "mcao3": mcao3, "kaos": kaos, "dkist-scao": dkist_scao,
            "dkist-scao-5cm": dkist_scao_5cm, "est-mcao": est_mcao,
            "est-mcao-solar": est_mcao_solar}


def names() -> list[str]:
    """Names of the presets."""
    return list(_PRESETS)


def get(name: str) -> SimulationConfig:
    """Return the preset ``name`` (see :func:`names`) as a :class:`SimulationConfig`."""
    if name not in _PRESETS:
        raise ValueError(f"`name` must be one of {', '.join(_PRESETS)}; got {name!r}.")
    return _PRESETS[name]()
