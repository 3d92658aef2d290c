"""`Simulation.set_state`: positions and velocities set between steps, made consistent with the
constraints, and the motion after them that of a run started there."""

import numpy as np
import pytest

import flexmb


@pytest.fixture(scope="module")
def pendulum(models):
    return flexmb.load(models / "pendulum.toml")


def spinning(models, tmp_path, omega):
    text = (models / "pendulum.toml").read_text()
    given = "angular_velocity = [0.0, 0.0, 0.0]"
    assert given in text
    path = tmp_path / "spinning.toml"
    path.write_text(text.replace(given, f"angular_velocity = [0.0, 0.0, {omega!r}]"))
    return flexmb.load(path)


def test_the_coordinates_have_names(pendulum):
    names = pendulum.simulation(t_end=1.0).coordinate_names
    assert names["positions"] == ["pendulum.R.x", "pendulum.R.y", "pendulum.R.z", "pendulum.p.0", "pendulum.p.1", "pendulum.p.2", "pendulum.p.3"]
    assert names["velocities"] == ["pendulum.Rdot.x", "pendulum.Rdot.y", "pendulum.Rdot.z", "pendulum.omega.x", "pendulum.omega.y", "pendulum.omega.z"]


def test_velocities_set_at_the_start_run_the_trajectory_of_a_run_started_with_them(pendulum, models, tmp_path):
    fresh = spinning(models, tmp_path, 2.0)
    start = fresh.simulation(t_end=2.0, rtol=1e-9, atol=1e-9)
    expected = fresh.simulate(t_end=2.0, rtol=1e-9, atol=1e-9)
    simulation = pendulum.simulation(t_end=2.0, rtol=1e-9, atol=1e-9)
    change = simulation.set_state(velocities=start.velocities)
    assert change["velocity_change"] < 1e-12 and change["velocity_residual"] < 1e-12
    results = simulation.run()
    assert np.max(np.abs(results.values - expected.values)) < 1e-9


def test_the_motion_after_a_state_set_mid_run_is_that_of_a_run_started_there(pendulum):
    # The pendulum is autonomous: set back to its initial state at t_s, it repeats its motion from t_s.
    span = 1.5
    reference = pendulum.simulation(t_end=span, rtol=1e-10, atol=1e-10)
    q0, v0 = reference.positions, reference.velocities
    reference.run()
    simulation = pendulum.simulation(t_end=10.0, rtol=1e-10, atol=1e-10)
    t_s = simulation.advance_to(0.73)
    change = simulation.set_state(positions=q0, velocities=v0)
    assert change["assembly_iterations"] == 0 and change["energy_change"] == pytest.approx(0.0, abs=1e-6)
    simulation.advance_to(t_s + span)
    later = simulation.time - t_s
    assert later >= span
    again = pendulum.simulation(t_end=later, rtol=1e-10, atol=1e-10).run()
    angle_set = simulation.results["pivot_angle"]
    times = simulation.results.time
    after = times > t_s
    expected = np.interp(times[after] - t_s, again.time, again["pivot_angle"])
    # The outputs after t_s (on the grid) against the fresh run's, interpolated linearly between its
    # outputs every 0.01 s: the interpolation error (|θ''| h²/8 ≈ 1e-4) bounds the difference.
    assert np.max(np.abs(angle_set[after] - expected)) < 2e-4


def test_positions_off_the_constraints_are_projected(pendulum):
    simulation = pendulum.simulation(t_end=1.0)
    q = simulation.positions.copy()
    q[0] += 0.1  # the pivot moved off the ground's marker
    change = simulation.set_state(positions=q)
    assert change["assembly_iterations"] > 0 and change["position_residual"] < 1e-9
    assert change["position_change"] == pytest.approx(0.1, abs=1e-3)
    assert abs(simulation.positions[0]) < 1e-9
    assert len(simulation.run()) == 101


def test_wrong_lengths_and_values_are_value_errors(pendulum):
    simulation = pendulum.simulation(t_end=1.0)
    with pytest.raises(ValueError, match="the positions must have 7 entries"):
        simulation.set_state(positions=np.zeros(5))
    with pytest.raises(ValueError, match="the velocities must have 6 entries"):
        simulation.set_state(velocities=[0.0] * 7)
    with pytest.raises(ValueError, match="the velocities must be finite, entry 2 is NaN"):
        simulation.set_state(velocities=[0.0, 0.0, float("nan"), 0.0, 0.0, 0.0])
    simulation.advance_to(1.0)
    assert simulation.finished
