"""Python in the loop: force laws and driver motions given as Python callables (`Model.with_law`)."""

import math

import numpy as np
import pytest

import flexmb

GAINS = {"k_p": 200.0, "k_d": 20.0, "theta_set": 0.5}


def pd_law(t, measures):
    angle, rate = measures
    return -GAINS["k_p"] * (angle - GAINS["theta_set"]) - GAINS["k_d"] * rate


@pytest.fixture(scope="module")
def pd_pendulum(models):
    return flexmb.load(models / "pd_pendulum.toml")


def test_a_controller_as_a_callable_runs_the_trajectory_of_the_same_expression(pd_pendulum):
    assert pd_pendulum.parameters["k_p"] == GAINS["k_p"] and pd_pendulum.parameters["theta_set"] == GAINS["theta_set"]
    expression = pd_pendulum.simulate()
    calls = []

    def counted(t, measures):
        calls.append(t)
        return pd_law(t, measures)

    controlled = pd_pendulum.with_law("controller", counted, measures=["pivot_angle", "pivot_rate"])
    assert controlled.laws == ["controller"] and pd_pendulum.laws == []
    results = controlled.simulate()
    assert results.columns == expression.columns
    assert np.max(np.abs(results.values - expression.values)) < 1e-12
    assert results.stats["steps"] == expression.stats["steps"]
    assert len(calls) > results.stats["residual_evaluations"]


def test_the_controlled_pendulum_settles_at_the_static_offset(pd_pendulum):
    # k_p (θ_set − θ) = m g L sin θ at rest (m = 1 kg, L = 1 m), solved by fixed-point iteration.
    theta = GAINS["theta_set"]
    for _ in range(50):
        theta = GAINS["theta_set"] - 9.81 * math.sin(theta) / GAINS["k_p"]
    controlled = pd_pendulum.with_law("controller", pd_law, measures=["pivot_angle", "pivot_rate"])
    angle = controlled.simulate(t_end=4.0)["pivot_angle"]
    assert abs(angle[-1] - theta) < 1e-6
    assert GAINS["theta_set"] - theta == pytest.approx(0.02254, abs=1e-5)
    assert np.max(angle) > theta  # it overshoots (damping ratio about 0.7)


def test_a_driver_motion_as_a_callable_runs_the_trajectory_of_the_expression_driver(models):
    crank = flexmb.load(models / "slider_crank.toml")
    expression = crank.simulate(t_end=1.0)
    omega = 2.0 * math.pi
    driven = crank.with_law("crank_motion", lambda t: (omega * t, omega, 0.0))
    results = driven.simulate(t_end=1.0)
    assert np.max(np.abs(results.values - expression.values)) < 1e-9


def test_an_exception_in_the_law_stops_the_run_naming_the_law_and_the_time(pd_pendulum):
    def law(t, measures):
        if t >= 0.5:
            return 1.0 / 0.0
        return pd_law(t, measures)

    failing = pd_pendulum.with_law("controller", law, measures=["pivot_angle", "pivot_rate"])
    with pytest.raises(flexmb.SimulationError) as raised:
        failing.simulate()
    message = str(raised.value)
    assert "the law `controller` failed" in message and "at t = 0.5" in message, message
    assert "ZeroDivisionError" in message, message
    assert isinstance(raised.value.__cause__, ZeroDivisionError)
    time = raised.value.results.time
    assert len(time) >= 50 and time[-1] < 0.5
    # The same model runs again (the failure belongs to that run), and a stepping simulation fails alike.
    simulation = failing.simulation(t_end=1.0)
    simulation.advance_to(0.25)
    with pytest.raises(flexmb.SimulationError) as raised:
        simulation.advance_to(1.0)
    assert isinstance(raised.value.__cause__, ZeroDivisionError)


def test_a_driver_law_must_return_the_motion_and_its_derivatives(models):
    crank = flexmb.load(models / "slider_crank.toml").with_law("crank_motion", lambda t: 2.0 * math.pi * t)
    with pytest.raises(flexmb.SimulationError) as raised:
        crank.simulate(t_end=0.1)
    assert "returns (f, f', f'')" in str(raised.value)
    assert isinstance(raised.value.__cause__, TypeError)


def test_unknown_names_are_model_errors(pd_pendulum):
    with pytest.raises(flexmb.ModelError, match="no driver named 'motor'.*force elements: controller"):
        pd_pendulum.with_law("motor", pd_law)
    with pytest.raises(flexmb.ModelError, match="no measure named 'speed': it has pivot_angle, pivot_rate"):
        pd_pendulum.with_law("controller", pd_law, measures=["speed"])
    with pytest.raises(flexmb.ModelError, match="give no component"):
        pd_pendulum.with_law("controller", pd_law, measures=["pivot_angle"], component="x")


def test_a_checkpoint_resumes_only_with_the_same_laws(pd_pendulum, tmp_path):
    controlled = pd_pendulum.with_law("controller", pd_law, measures=["pivot_angle", "pivot_rate"])
    first = controlled.simulation(t_end=2.0)
    first.advance_to(1.0)
    first.save(tmp_path / "state.json")
    with pytest.raises(flexmb.ModelError, match=r"laws given as code \[controller\], the model given has \[\]"):
        flexmb.Simulation.resume(pd_pendulum, tmp_path / "state.json", t_end=2.0)
    rest = flexmb.Simulation.resume(controlled, tmp_path / "state.json", t_end=2.0).run()
    whole = controlled.simulate(t_end=2.0)
    assert len(first.results) + len(rest) == len(whole)
    assert np.max(np.abs(rest.values - whole.values[len(first.results):])) < 1e-12
