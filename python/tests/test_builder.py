"""flexmb.ModelBuilder: a model built in code with the model file's keys gives the file's model — the
same results to the last bit — and the file's error messages, with the builder call that made the
table; flexible bodies by the path of their FE model file."""

import numpy as np
import pytest

import flexmb
from conftest import REPOSITORY


def pendulum_builder(length=1.0):
    """models/pendulum.toml, table for table."""
    m = flexmb.ModelBuilder("pendulum", gravity=[0.0, -9.81, 0.0])
    m.simulation(t_end=5.0, output_step=0.01, rtol=1e-6, atol=1e-6)
    m.parameter("L", length).parameter("m_bob", 1.0).parameter("r_bob", 0.02)
    m.body(
        "pendulum",
        mass="m_bob",
        inertia=["0.4*m_bob*r_bob^2"] * 3,
        center_of_mass=[0.0, "-L", 0.0],
        position=[0.0, 0.0, 0.0],
        orientation={"axis": [0, 0, 1], "angle_deg": 60},
        velocity=[0.0, 0.0, 0.0],
        angular_velocity=[0.0, 0.0, 0.0],
    )
    m.marker("pivot_ground", body="ground", origin=[0.0, 0.0, 0.0])
    m.marker("pivot_pendulum", body="pendulum", origin=[0.0, 0.0, 0.0])
    m.marker("bob", body="pendulum", origin=[0.0, "-L", 0.0])
    m.joint("pivot", type="revolute", i="pivot_ground", j="pivot_pendulum")
    m.measure("pivot_angle", type="joint_angle", joint="pivot")
    m.output(type="marker_position", marker="bob")
    m.output(type="joint_reaction", joint="pivot")
    m.output("measure", measure="pivot_angle")
    m.output(type="energy")
    m.output(type="constraint_residual")
    return m


def test_the_pendulum_built_in_code_gives_the_files_results_to_the_last_bit(models):
    built = pendulum_builder().build()
    from_file = flexmb.load(models / "pendulum.toml")
    assert built.name == "pendulum" and built.file == "<ModelBuilder pendulum>"
    assert built.columns == from_file.columns
    assert built.parameters == from_file.parameters
    assert built.defaults == from_file.defaults
    a, b = built.simulate(), from_file.simulate()
    assert a.values.shape == (501, len(built.columns))
    assert np.array_equal(a.values, b.values)
    assert a.stats["steps"] == b.stats["steps"]
    assert a.stats["newton_iterations"] == b.stats["newton_iterations"]


def test_parameters_of_the_builder_and_of_build_are_those_of_the_file(models):
    a = pendulum_builder(length=2.0).build().simulate(t_end=1.0)
    b = flexmb.load(models / "pendulum.toml", parameters={"L": 2.0}).simulate(t_end=1.0)
    c = pendulum_builder().build(parameters={"L": 2.0}).simulate(t_end=1.0)
    assert np.array_equal(a.values, b.values) and np.array_equal(c.values, b.values)


def test_the_text_saved_as_a_file_loads_as_the_same_model(tmp_path):
    builder = pendulum_builder()
    path = tmp_path / "pendulum.toml"
    path.write_text(builder.to_toml())
    saved = flexmb.load(path).simulate(t_end=1.0)
    assert np.array_equal(saved.values, builder.build().simulate(t_end=1.0).values)
    assert '[[joint]]\nname = "pivot"\ntype = "revolute"' in builder.to_toml()
    assert 'orientation = { axis = [0, 0, 1], angle_deg = 60 }' in builder.to_toml()


def test_a_builder_error_names_the_key_path_and_the_call_that_made_it():
    m = pendulum_builder()
    m.body("second", mass=-1.0, inertia=[1, 1, 1])
    with pytest.raises(flexmb.ModelError) as caught:
        m.build()
    message = str(caught.value)
    # The file's message: the generated text's name and line, the key path, what is wrong …
    assert message.startswith("<ModelBuilder pendulum>:"), message
    assert "body[1].mass: mass must be positive and finite, got -1" in message, message
    # … and the builder call that made the table, with the script's line.
    assert "(made by body('second') at " in message and "test_builder.py:" in message, message
    line = int(message.split(":")[1])
    assert m.to_toml().splitlines()[line - 1] == "mass = -1.0"


def test_a_misspelt_key_and_a_misspelt_name_get_the_files_suggestions():
    m = pendulum_builder()
    m.marker("tip", body="pendulm", origin=[0, 0, 0])
    with pytest.raises(flexmb.ModelError, match=r"marker\[3\]\.body: .*did you mean `pendulum`\?.*made by marker\('tip'\)"):
        m.build()
    m = pendulum_builder()
    m.joint("slide", type="prismatic", i="pivot_ground", j="bob", axes=[0, 0, 1])
    with pytest.raises(flexmb.ModelError, match=r"joint\[1\]"):
        m.build()


def test_values_that_a_model_file_cannot_hold_are_refused_before_loading():
    m = flexmb.ModelBuilder("x")
    m.body("b", mass=object())
    with pytest.raises(TypeError, match=r"body\[0\]\.mass: cannot write a object"):
        m.to_toml()


def test_numpy_values_are_written_as_numbers(models):
    m = pendulum_builder()
    m.parameter("L", np.float64(1.0))
    m.marker("extra", body="pendulum", origin=np.array([0.0, -0.5, 0.0]))
    assert "L = 1.0" in m.to_toml() and "origin = [0.0, -0.5, 0.0]" in m.to_toml()
    assert m.build().check()["markers"] == 4


def flexible_pendulum_builder(fe_model, base_dir):
    """models/flexible_pendulum.toml with its beam reduced from the FE model file at `fe_model`."""
    m = flexmb.ModelBuilder("flexible_pendulum", gravity=[0.0, -9.81, 0.0], base_dir=base_dir)
    m.simulation(t_end=2.0, output_step=0.002, rtol=1e-6, atol=1e-6)
    m.flexible_body("beam", fe_model=fe_model, damping={"ratio": 0.02}, position=[0.0, 0.0, 0.0],
                    velocity=[0.0, 0.0, 0.0], angular_velocity=[0.0, 0.0, 0.0])
    m.marker("hinge_ground", body="ground")
    m.marker("hinge_beam", body="beam", node="arm.start")
    m.joint("hinge", type="revolute", i="hinge_ground", j="hinge_beam")
    m.output(type="node_position", body="beam", node=[1.0, 0.0, 0.0])
    m.output(type="node_velocity", body="beam", node=21)
    m.output(type="node_deformation", body="beam", node=21)
    m.output(type="modal_coordinates", body="beam")
    m.output(type="energy")
    m.output(type="joint_reaction", joint="hinge")
    m.output(type="constraint_residual")
    return m


def test_a_flexible_body_by_the_path_of_its_fe_model_file(models):
    built = flexible_pendulum_builder("fe/pendulum_beam.toml", base_dir=models).build()
    from_file = flexmb.load(models / "flexible_pendulum.toml")
    body = built.check()["flexible_bodies"][0]
    assert body["mode_set"] == "4N" and body["nodes"] == 21
    assert body["frequencies_hz"] == from_file.check()["flexible_bodies"][0]["frequencies_hz"]
    a, b = built.simulate(t_end=0.2), from_file.simulate(t_end=0.2)
    assert np.array_equal(a.values, b.values)
    # A relative path starts at the current directory when no base_dir is given; an absolute one anywhere.
    absolute = flexible_pendulum_builder(models / "fe" / "pendulum_beam.toml", base_dir=None).build()
    assert absolute.check()["flexible_bodies"][0]["frequencies_hz"] == body["frequencies_hz"]


def test_a_missing_fe_model_file_is_the_files_error(tmp_path):
    m = flexible_pendulum_builder("no_such_beam.toml", base_dir=tmp_path)
    with pytest.raises(flexmb.ModelError, match=r"flexible_body\[0\]"):
        m.build()
