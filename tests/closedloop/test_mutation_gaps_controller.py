"""closedloop.control.controller: the control law, frame by frame, against equations by hand.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/control/controller.py").
References, from outside the code under test (the module docstring's timing model,
restated here):

- the weights of the commands seen by frame k, worked out by hand from the timing:
  frame k integrates over [-iota, 0] (frames, relative to its end) and command c_{k-j}
  is applied on [delta - j, delta - j + 1); e.g. delta = 0.5, iota = 1 sees c_{k-1} and
  c_{k-2} half each;
- the classic integrator ``c_k = (1 - leak) c_{k-1} + g m_k`` (no predictor) and the POL
  ``p_k = m_k + sum_j w_j c_{k-j}``, iterated in the test;
- the lead ``L = delta + 1/2 + iota/2`` and the linear interpolation of a forecast
  between horizons floor(L) and floor(L) + 1 (horizon 0 = p_k), written by hand for a
  predictor whose forecasts are set in the test;
- a fault's documented outcome (raise naming predictor, step and mode; or hold c_{k-1}).
"""

from __future__ import annotations

import numpy as np
import pytest

from closedloop.control.controller import Controller, PredictorFault, lead_frames


class _Known:
    """A predictor whose forecast for horizon h at step k is ``pol + 10 h + k`` (per mode)."""

    def __init__(self, horizon, bad=None):
        self.horizon = horizon
        self.resets = 0
        self.updates = []
        self.bad = bad or {}

    def reset(self):
        self.resets += 1
        self.updates.clear()

    def update(self, pol):
        k = len(self.updates)
        self.updates.append(np.array(pol))
        if k in self.bad:
            return self.bad[k]
        return np.array([pol + 10.0 * h + k for h in range(1, self.horizon + 1)])


@pytest.mark.parametrize("delay, integration, weights", [
    (0.5, 1.0, [0.0, 0.5, 0.5]),
    (1.0, 1.0, [0.0, 0.0, 1.0]),
    (0.0, 1.0, [0.0, 1.0]),
    (0.75, 0.5, [0.0, 0.5, 0.5]),
    (1.25, 0.5, [0.0, 0.0, 1.0]),
])
def test_integrator_and_pol_frame_by_frame(delay, integration, weights):
    rng = np.random.default_rng(1)
    gain, leak = 0.3, 0.05
    ctl = Controller(3, gain=gain, leak=leak, delay_frames=delay,
                     integration_frames=integration)
    assert ctl.weights == pytest.approx(weights, abs=1e-15)
    assert ctl.lead == delay + 0.5 + integration / 2
    past = [np.zeros(3)] * 4  # c_{k-1}, c_{k-2}, ... (newest first)
    for _ in range(8):
        m = rng.standard_normal(3)
        seen = sum(w * past[j - 1] for j, w in enumerate(weights) if j > 0)
        assert ctl.seen_commands() == pytest.approx(seen, rel=1e-12, abs=1e-15)
        command, pol, forecast = ctl.step(m)
        expected = (1 - leak) * past[0] + gain * m
        assert command == pytest.approx(expected, rel=1e-12, abs=1e-14)
        assert pol == pytest.approx(m + seen, rel=1e-12, abs=1e-15)
        assert forecast is pol
        past = [command, *past[:-1]]
        assert np.array_equal(ctl.command, command)


@pytest.mark.parametrize("delay, integration", [(0.5, 1.0), (1.0, 1.0), (0.0, 0.5),
                                                (0.0, 1.0), (1.5, 0.5)])
def test_forecast_is_interpolated_over_the_lead(delay, integration):
    lead = lead_frames(delay, integration)
    assert lead == delay + 0.5 + integration / 2
    horizon = int(np.ceil(lead))
    pred = _Known(horizon)
    gain, leak = 0.4, 0.1
    ctl = Controller(2, gain=gain, leak=leak, delay_frames=delay,
                     integration_frames=integration, predictor=pred)
    assert pred.resets == 1
    rng = np.random.default_rng(2)
    prev = np.zeros(2)
    for k in range(5):
        seen = ctl.seen_commands()
        m = rng.standard_normal(2)
        command, pol, forecast = ctl.step(m)
        # forecast at horizon h is pol + 10 h + k (horizon 0: pol), linear in h
        assert forecast == pytest.approx(pol + 10.0 * lead + k * min(lead, 1.0), rel=1e-12)
        assert command == pytest.approx((1 - leak) * prev + gain * (forecast - seen),
                                        rel=1e-12)
        assert np.array_equal(pred.updates[-1], pol)
        prev = command


def test_horizon_must_cover_the_lead():
    with pytest.raises(ValueError) as exc:
        Controller(2, gain=0.3, leak=0.0, delay_frames=0.5, integration_frames=1.0,
                   predictor=_Known(1))
    assert str(exc.value) == ("`predictor.horizon` must be >= 2 (the lead of 1.5 frames "
                              "rounded up); got 1.")
    Controller(2, gain=0.3, leak=0.0, delay_frames=0.5, integration_frames=1.0,
               predictor=_Known(2))  # the boundary

    pred = _Known(1)
    del pred.horizon
    # without a horizon attribute the predictor is taken as one-step-ahead
    Controller(2, gain=0.3, leak=0.0, delay_frames=0.0, integration_frames=1.0,
               predictor=pred)
    with pytest.raises(ValueError, match="got 1"):
        Controller(2, gain=0.3, leak=0.0, delay_frames=0.5, integration_frames=1.0,
                   predictor=pred)


def test_projector_keeps_only_the_observable_change():
    pred = _Known(2)
    p = np.array([[1.0, 0.0], [0.0, 0.0]])  # mode 1 is not seen by any WFS
    ctl = Controller(2, gain=0.5, leak=0.0, delay_frames=0.5, integration_frames=1.0,
                     predictor=pred, projector=p.astype(int).tolist())
    assert ctl.projector.dtype == np.float64 and ctl.n_modes == 2
    _, pol, forecast = ctl.step(np.array([1.0, 2.0]))
    assert forecast[0] == pytest.approx(pol[0] + 15.0) and forecast[1] == pol[1]
    # an external forecast (the oracle's) is used as it is, and the predictor not updated
    ext = np.array([7.0, 8.0])
    _, _, forecast = ctl.step(np.array([0.0, 0.0]), forecast_pol=ext)
    assert forecast is ext and len(pred.updates) == 1


def test_projector_and_action_messages():
    kw = dict(gain=0.3, leak=0.0, delay_frames=0.5, integration_frames=1.0)
    with pytest.raises(ValueError) as exc:
        Controller(2, projector=np.eye(3), **kw)
    assert str(exc.value) == "`projector` must be a finite (2, 2) array; got shape (3, 3)."
    with pytest.raises(ValueError, match="projector"):
        Controller(2, projector=np.array([[1.0, np.nan], [0.0, 1.0]]), **kw)
    with pytest.raises(ValueError) as exc:
        Controller(2, on_predictor_fault="skip", **kw)
    assert str(exc.value) == ("`on_predictor_fault` must be one of 'raise', 'hold'; got "
                              "'skip'.")


def test_hold_keeps_the_last_command_counts_and_resets():
    pred = _Known(2, bad={2: np.full((2, 2), np.nan), 3: "x"})
    ctl = Controller(2, gain=0.5, leak=0.2, delay_frames=0.5, integration_frames=1.0,
                     predictor=pred, on_predictor_fault="hold")
    c0, _, _ = ctl.step(np.array([1.0, -1.0]))
    c1, _, _ = ctl.step(np.array([0.5, 0.5]))
    seen = 0.5 * c1 + 0.5 * c0
    c2, pol, forecast = ctl.step(np.array([0.25, 0.0]))
    assert np.array_equal(c2, c1)
    held = c2.copy()
    assert pol == pytest.approx(np.array([0.25, 0.0]) + seen) and forecast is pol
    assert ctl.n_faults == 1
    # the held command counts as the command of that frame in what later frames see
    assert ctl.seen_commands() == pytest.approx(0.5 * c2 + 0.5 * c1)
    c3, _, _ = ctl.step(np.zeros(2))  # a non-numeric forecast: held too
    assert np.array_equal(c3, c1) and ctl.n_faults == 2
    c4, _, _ = ctl.step(np.zeros(2))
    assert not np.array_equal(c4, c1)
    assert np.array_equal(c2, held)  # what was returned is not a view of the history
    ctl.reset()
    assert ctl.n_faults == 0 and pred.resets == 2 and not ctl.command.any()
    assert not ctl.seen_commands().any()
    c0_again, _, _ = ctl.step(np.array([1.0, -1.0]))
    assert np.array_equal(c0_again, c0)  # step 0 again: the same forecast, the same bits


def test_reset_without_a_predictor_clears_the_commands():
    ctl = Controller(2, gain=0.5, leak=0.0, delay_frames=1.0, integration_frames=1.0)
    first, _, _ = ctl.step(np.ones(2))
    ctl.step(np.ones(2))
    ctl.reset()
    assert not ctl._history.any()
    again, _, _ = ctl.step(np.ones(2))
    assert np.array_equal(again, first)


@pytest.mark.parametrize("bad, message, mode", [
    (np.zeros(2), "predictor _Known returned shape (2,) at step 1; the loop needs exactly "
                  "(2, 2) (horizons x modes) (on_predictor_fault='hold' keeps the last "
                  "command instead).", None),
    ("abc", "predictor _Known returned str at step 1, not an array of numbers "
            "(on_predictor_fault='hold' keeps the last command instead).", None),
    (np.array([[0.0, 1.0], [np.inf, 2.0]]), "predictor _Known returned inf at step 1 for "
     "mode 0 (horizon 2) (on_predictor_fault='hold' keeps the last command instead).", 0),
    (np.array([[0.0, 1.0], [3.0, -np.inf]]), "predictor _Known returned -inf at step 1 for "
     "mode 1 (horizon 2) (on_predictor_fault='hold' keeps the last command instead).", 1),
])
def test_fault_messages_name_predictor_step_and_mode(bad, message, mode):
    ctl = Controller(2, gain=0.5, leak=0.0, delay_frames=0.5, integration_frames=1.0,
                     predictor=_Known(2, bad={1: bad}))
    ctl.step(np.zeros(2))
    with pytest.raises(PredictorFault) as exc:
        ctl.step(np.zeros(2))
    assert str(exc.value) == message
    assert exc.value.step == 1 and exc.value.mode == mode
    assert isinstance(exc.value.mode, (int, type(None)))
    assert ctl.n_faults == 0


def test_a_held_frame_shifts_every_past_command():
    # delay 1.5, exposure 1: frame k sees c_{k-2} and c_{k-3} half each (weights by hand)
    pred = _Known(3, bad={3: np.full((3, 2), np.nan)})
    ctl = Controller(2, gain=0.5, leak=0.0, delay_frames=1.5, integration_frames=1.0,
                     predictor=pred, on_predictor_fault="hold")
    assert ctl.weights == pytest.approx([0.0, 0.0, 0.5, 0.5])
    c = [ctl.step(m)[0] for m in (np.array([1.0, 0.0]), np.array([0.0, 2.0]),
                                   np.array([3.0, 1.0]))]
    held, _, _ = ctl.step(np.zeros(2))
    assert np.array_equal(held, c[2])
    # history now c_3 = c_2 (held), c_2, c_1: the next frame sees c_2 and c_1 half each
    assert ctl.seen_commands() == pytest.approx(0.5 * c[2] + 0.5 * c[1])


def test_steps_count_from_zero_again_after_reset():
    pred = _Known(2, bad={0: np.zeros(3)})
    ctl = Controller(2, gain=0.5, leak=0.0, delay_frames=0.5, integration_frames=1.0,
                     predictor=pred)
    with pytest.raises(PredictorFault) as exc:
        ctl.step(np.zeros(2))
    assert exc.value.step == 0
    ctl.reset()
    with pytest.raises(PredictorFault) as exc:
        ctl.step(np.zeros(2))
    assert exc.value.step == 0 and "at step 0;" in str(exc.value)
