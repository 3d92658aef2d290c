"""Runs into numpy arrays: shapes, physics of the shipped pendulum, statistics, pandas."""

import math
import sys

import numpy as np
import pytest

import flexmb


def complete_elliptic_integral_k(k):
    """K(k) = ∫₀^{π/2} dθ / √(1 − k² sin²θ), by the arithmetic-geometric mean: π / (2 AGM(1, √(1 − k²)))."""
    a, b = 1.0, math.sqrt(1.0 - k * k)
    while abs(a - b) > 1e-16 * a:
        a, b = 0.5 * (a + b), math.sqrt(a * b)
    return math.pi / (2.0 * a)


def zero_crossings(time, values):
    """The times where `values` changes sign, by linear interpolation between output times."""
    crossings = []
    for i in range(len(values) - 1):
        if values[i] == 0.0 or values[i] * values[i + 1] < 0.0:
            crossings.append(time[i] - values[i] * (time[i + 1] - time[i]) / (values[i + 1] - values[i]))
    return crossings


def test_columns_are_numpy_arrays_with_a_value_per_output_time(models):
    model = flexmb.load(models / "pendulum.toml")
    results = model.simulate(t_end=0.75, output_step=0.05)
    assert results.columns == model.columns and results.columns[0] == "t"
    assert len(results.units) == len(results.columns) and results.units[0] == "s"
    np.testing.assert_allclose(results.time, np.arange(16) * 0.05, rtol=0, atol=1e-14)
    for name in results.columns:
        assert isinstance(results[name], np.ndarray) and results[name].shape == (16,), name
    assert results.values.shape == (16, len(results.columns))
    np.testing.assert_array_equal(results.values[:, 0], results.time)
    assert "pivot_angle" in results and "nothing" not in results
    with pytest.raises(KeyError, match="no output column 'nothing'"):
        results["nothing"]


def test_the_pendulum_swings_with_the_closed_form_period_and_keeps_its_energy(models):
    # A physical pendulum released from rest at 60°: T = 4 √(I_O / (m g L)) K(sin 30°), with I_O the
    # inertia about the pivot (the bob a solid sphere of radius r on a massless rod of length L).
    model = flexmb.load(models / "pendulum.toml")
    results = model.simulate(t_end=5.0, rtol=1e-9, atol=1e-9)
    m, length, r, g = 1.0, 1.0, 0.02, 9.81
    inertia = m * length**2 + 0.4 * m * r**2
    period = 4.0 * math.sqrt(inertia / (m * g * length)) * complete_elliptic_integral_k(math.sin(math.pi / 6))
    crossings = zero_crossings(results.time, results["pivot_angle"])
    assert len(crossings) == 5  # 5 s: a little over two periods
    # A quarter period to the bottom, then half periods (measured within 3.1e-7 s of the closed form at
    # 1e-9; linear interpolation over 0.01 s of an angle whose curvature vanishes at the crossing adds
    # little).
    assert abs(crossings[0] - period / 4) < 1e-6, (crossings, period)
    for a, b in zip(crossings, crossings[1:]):
        assert abs((b - a) - period / 2) < 1e-6, (crossings, period)
    energy = results["energy.total"]
    assert abs(energy[0] - (-m * g * length * math.cos(math.pi / 3))) < 1e-12
    assert np.max(np.abs(energy - energy[0])) < 2e-6  # measured 5.1e-7 J
    assert abs(results["pivot_angle"][0] - math.pi / 3) < 1e-12


def test_stats_and_summary_are_the_program_s_json_summary(models):
    results = flexmb.load(models / "pendulum.toml").simulate(t_end=1.0)
    summary = results.summary
    assert summary["status"] == "completed" and summary["model"] == "pendulum"
    assert summary["settings"]["t_end"] == 1.0 and summary["settings"]["integrator"] == "bdf"
    assert summary["output"]["rows"] == len(results) == 101
    assert [c["name"] for c in summary["output"]["columns"]] == results.columns[1:]
    stats = results.stats
    assert stats == summary["statistics"]
    assert stats["steps"] > 10 and stats["newton_iterations"] >= stats["steps"]
    for key in ["rejected_steps", "error_test_failures", "newton_failures", "jacobian_evaluations", "matrix_factorizations"]:
        assert isinstance(stats[key], int), key
    assert sum(stats["steps_per_order"].values()) == stats["steps"]


def test_every_integrator_swings_the_pendulum_alike(models):
    model = flexmb.load(models / "pendulum.toml")
    reference = model.simulate(t_end=1.0, rtol=1e-10, atol=1e-10)["pivot_angle"]
    for integrator in ["bdf", "adams", "gen-alpha"]:
        results = model.simulate(t_end=1.0, integrator=integrator, rtol=1e-7, atol=1e-7)
        assert results.summary["settings"]["integrator"] == integrator
        assert np.max(np.abs(results["pivot_angle"] - reference)) < 1e-4, integrator


def test_to_pandas_gives_a_data_frame_or_a_clear_import_error(models, monkeypatch):
    results = flexmb.load(models / "pendulum.toml").simulate(t_end=0.1)
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match="pip install pandas"):
        results.to_pandas()
    monkeypatch.undo()
    pandas = pytest.importorskip("pandas")
    frame = results.to_pandas()
    assert isinstance(frame, pandas.DataFrame)
    assert list(frame.columns) == results.columns
    np.testing.assert_array_equal(frame["pivot_angle"].to_numpy(), results["pivot_angle"])


def test_a_failing_run_raises_simulation_error_with_the_program_s_message_and_the_rows_before(models, program, tmp_path):
    # The pivot driven by sqrt(0.05 − t), whose rate is infinite at t = 0.05 s: the run stops there, and
    # the message names the driver and its rate (found ahead of the steps that shrank to nothing).
    driver = '[[driver]]\nname = "runaway"\njoint = "pivot"\nfunction = "sqrt(0.05 - t)"\n\n[[output]]'
    path = tmp_path / "runaway.toml"
    path.write_text((models / "pendulum.toml").read_text().replace("[[output]]", driver, 1))
    printed = program("run", path, "--t-end", "1", "--out", tmp_path, "--quiet", check=False)
    assert printed.returncode != 0
    with pytest.raises(flexmb.SimulationError) as raised:
        flexmb.load(path).simulate(t_end=1.0)
    message = str(raised.value)
    assert isinstance(raised.value, RuntimeError)
    assert f"{path}: simulation failed: " in message and "at t = 0.05 s joint 'runaway'" in message and "is not finite" in message
    assert printed.stderr.splitlines()[0] == f"error: {message}"
    results = raised.value.results
    assert results.summary["status"] == "failed" and results.summary["error"] in message
    written = len((tmp_path / "runaway.csv").read_text().splitlines()) - 1
    assert len(results) == written and 0 < written <= 6  # t = 0 … 0.05 at most
    assert results.time[-1] <= 0.05


def test_global_error_control_returns_the_run_made_again_at_the_tolerance_it_asks_for(models):
    # models/four_bar.toml turns global error control on: its run at rtol 1e-6 is estimated about 18
    # tolerances off, so it is made again at rtol / 18; the results are that run's, the same numbers as
    # a run asked for at that rtol directly, without the control.
    text = (models / "four_bar.toml").read_text()
    assert "global_error_control = true" in text
    model = flexmb.load(models / "four_bar.toml")
    controlled = model.simulate()
    control = controlled.stats["global_error_control"]
    assert control["asked_rtol"] == 1e-6 and len(control["earlier_runs"]) == 1, control
    first = control["earlier_runs"][0]
    assert first["rtol"] == 1e-6 and 15.0 < first["tolerances"] < 25.0, control
    assert control["rtol"] == pytest.approx(1e-6 / first["tolerances"], rel=1e-12), control
    assert controlled.stats["global_error_estimate"]["tolerances"] < 10.0, controlled.stats
    uncontrolled = flexmb.loads(text.replace("global_error_control = true", "global_error_estimate = true"))
    direct = uncontrolled.simulate(rtol=control["rtol"], atol=control["atol"])
    assert "global_error_control" not in direct.stats
    np.testing.assert_array_equal(direct.values, controlled.values)
