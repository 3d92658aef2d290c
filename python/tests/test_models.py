"""Loading model files with parameter overrides, checking them, and their errors: as the program does."""

import math

import pytest

import flexmb
from conftest import read_csv_text


def written(value):
    """`value` as the result CSV writes it and reads back: exactly (shortest round-trip digits)."""
    return value


def test_parameter_override_gives_the_program_s_csv_of_the_edited_file_to_the_last_digit(models, program, tmp_path):
    # The pendulum with its rod 2 m long instead of 1 m: the override in Python against the program run
    # on a copy of the file with the value edited.
    text = (models / "pendulum.toml").read_text()
    assert "L = 1.0 " in text
    edited = tmp_path / "pendulum.toml"
    edited.write_text(text.replace("L = 1.0 ", "L = 2.0 ", 1))
    program("run", edited, "--t-end", "1", "--out", tmp_path / "out", "--quiet")
    header, rows = read_csv_text(tmp_path / "out" / "pendulum.csv")

    model = flexmb.load(models / "pendulum.toml", parameters={"L": 2.0})
    assert model.parameters["L"] == 2.0
    results = model.simulate(t_end=1.0)
    assert results.columns == header
    assert len(results) == len(rows) == 101
    for name_index, name in enumerate(header):
        column = results[name]
        for row, value in zip(rows, column):
            assert written(value) == float(row[name_index]), f"{name}: {value!r} is written {row[name_index]}"

    # The override changes the swing: the bob hangs 2 m below the pivot.
    unchanged = flexmb.load(models / "pendulum.toml").simulate(t_end=1.0)
    assert abs(results["bob.position.y"][0] - 2 * unchanged["bob.position.y"][0]) < 1e-12
    assert abs(results["bob.position.y"][0] + 2.0 * math.cos(math.pi / 3)) < 1e-9


def test_check_reports_degrees_of_freedom_redundant_constraints_and_the_model_s_elements(models, program):
    path = models / "benchmarks" / "bricard_mechanism.toml"
    check = flexmb.load(path).check()
    printed = program("check", path).stdout
    assert f"degrees of freedom: {check['degrees_of_freedom']}\n" in printed
    assert check["degrees_of_freedom"] == 1
    assert len(check["redundant_constraints"]) == 1
    assert "joint 'j6' (revolute), equation 5" in check["redundant_constraints"][0]
    for description in check["redundant_constraints"]:
        assert f"  - {description}\n" in printed
    summary = (
        f"model '{check['model']}': {len(check['bodies'])} bodies, {check['markers']} markers, "
        f"{len(check['joints'])} joints ({check['constraint_equations']} constraint equations), "
        f"{len(check['force_elements'])} force elements"
    )
    assert summary in printed

    pendulum = flexmb.load(models / "pendulum.toml").check()
    assert pendulum["degrees_of_freedom"] == 1 and pendulum["redundant_constraints"] == []
    assert pendulum["bodies"] == ["pendulum"] and pendulum["joints"] == ["pivot"]
    assert pendulum["flexible_bodies"] == []


def test_a_bad_model_file_raises_model_error_with_the_program_s_message(program, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[model]\nname = "bad"\n\n[[body]]\nname = "b"\nmass = -1.0\ninertia = [1, 1, 1]\n')
    printed = program("check", bad, check=False)
    assert printed.returncode != 0
    with pytest.raises(flexmb.ModelError) as raised:
        flexmb.load(bad)
    message = str(raised.value)
    assert isinstance(raised.value, ValueError)
    assert printed.stderr.strip() == f"error: {message}"
    assert message == f"{bad}:6: body[0].mass: mass must be positive and finite, got -1"


def test_a_missing_file_and_an_unknown_parameter_raise_model_error(models, tmp_path):
    with pytest.raises(flexmb.ModelError, match="nowhere.toml"):
        flexmb.load(tmp_path / "nowhere.toml")
    with pytest.raises(flexmb.ModelError, match=r"the model has no parameter 'length' \(it has: L, m_bob, r_bob\)"):
        flexmb.load(models / "pendulum.toml", parameters={"length": 2.0})


def test_bad_run_arguments_raise_model_error(models):
    model = flexmb.load(models / "pendulum.toml")
    with pytest.raises(flexmb.ModelError, match="rtol must be a positive number, got -1"):
        model.simulate(rtol=-1.0)
    with pytest.raises(flexmb.ModelError, match="integrator"):
        model.simulate(integrator="rk4")
    with pytest.raises(flexmb.ModelError, match="output rows"):
        model.simulate(t_end=1e9, output_step=1e-3)


def test_new_output_columns_appear_in_results_by_name(models, tmp_path):
    # The spinning top with its 3-1-3 Euler angles and its angular momentum about the centre of mass:
    # the columns are the model's, by name, with no change to the package.
    text = (models / "spinning_top.toml").read_text()
    model_file = tmp_path / "top.toml"
    model_file.write_text(
        text
        + '\n[[output]]\ntype = "euler_angles"\nbody = "top"\n'
        + '\n[[output]]\ntype = "angular_momentum"\nbody = "top"\n'
    )
    results = flexmb.load(model_file).simulate(t_end=0.1)
    assert "top.angles_313.theta" in results.columns
    # The symmetry axis starts 30° from the vertical: the nutation angle θ of the 3-1-3 sequence.
    assert abs(results["top.angles_313.theta"][0] - math.radians(30)) < 1e-12
    # C w_s along the symmetry axis (0, -sin 30°, cos 30°): 0.5 N m s.
    assert abs(results["top.angular_momentum.z"][0] - 0.5 * math.cos(math.radians(30))) < 1e-12
