"""Stepping a simulation: pieces that make one run, state, checkpoints saved and resumed."""

import numpy as np
import pytest

import flexmb


def test_advance_to_in_two_pieces_equals_one_run(models):
    model = flexmb.load(models / "pendulum.toml")
    whole = model.simulate(t_end=1.0)
    simulation = model.simulation(t_end=1.0)
    reached = simulation.advance_to(0.5)
    # Steps are not shortened to land on the time asked for: the first step at or after it.
    assert reached == simulation.time >= 0.5 and not simulation.finished
    assert len(simulation.results) == int(reached / 0.01) + 1  # the output times up to the step's end
    assert simulation.advance_to(1.0) == 1.0 and simulation.finished
    pieces = simulation.results
    assert pieces.columns == whole.columns
    np.testing.assert_array_equal(pieces.values, whole.values)
    assert pieces.stats["steps"] == whole.stats["steps"]
    assert simulation.run().values.shape == whole.values.shape  # finished: nothing more


def test_state_is_positions_and_velocities_at_the_last_step(models):
    model = flexmb.load(models / "pendulum.toml")
    simulation = model.simulation(t_end=1.0)
    simulation.advance_to(0.3)
    q, v = simulation.positions, simulation.velocities
    assert q.shape == (7,) and v.shape == (6,)  # origin and Euler parameters; velocity and ω̄
    assert abs(np.dot(q[3:], q[3:]) - 1.0) < 1e-9
    # The pivot stays at the origin, and the body turns about z only.
    np.testing.assert_allclose(q[:3], 0.0, atol=1e-9)
    np.testing.assert_allclose(v[3:5], 0.0, atol=1e-9)


def test_a_saved_and_resumed_simulation_continues_the_run(models, tmp_path):
    # As `flexmb run --pause-at 0.5 --save-state` then `--resume`: the rows after the checkpoint's time
    # follow the first part's to make the rows of one run, and the summary counts the whole run.
    model = flexmb.load(models / "pendulum.toml")
    whole = model.simulate(t_end=1.0)
    first = model.simulation(t_end=1.0)
    first.advance_to(0.5)
    checkpoint = tmp_path / "state.json"
    first.save(checkpoint)
    resumed = flexmb.Simulation.resume(model, checkpoint, t_end=1.0)
    assert resumed.time == first.time
    rest = resumed.run()
    joined = np.vstack([first.results.values, rest.values])
    np.testing.assert_allclose(joined, whole.values, rtol=1e-12, atol=1e-14)
    assert rest.stats["steps"] == whole.stats["steps"]


def test_a_checkpoint_of_the_program_resumes_in_python(models, program, tmp_path):
    path = models / "pendulum.toml"
    checkpoint = tmp_path / "state.json"
    program("run", path, "--t-end", "1", "--pause-at", "0.5", "--save-state", checkpoint, "--out", tmp_path, "--quiet")
    model = flexmb.load(path)
    rest = flexmb.Simulation.resume(model, checkpoint, t_end=1.0).run()
    whole = model.simulate(t_end=1.0)
    np.testing.assert_allclose(rest.values, whole.values[-len(rest):], rtol=1e-12, atol=1e-14)


def test_a_file_that_is_not_a_checkpoint_raises_model_error(models, tmp_path):
    model = flexmb.load(models / "pendulum.toml")
    bad = tmp_path / "state.json"
    bad.write_text("{}")
    with pytest.raises(flexmb.ModelError, match="not a simulation checkpoint"):
        flexmb.Simulation.resume(model, bad)
