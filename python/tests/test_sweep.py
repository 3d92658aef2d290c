"""flexmb.sweep: a model's variants on local processes, on Ray and serially give the same table and the
same results to the last bit (the same library on the same inputs); the table carries the physics
(the pendulum's period); a failing variant fills its failure column and the others complete."""

import math
import pickle
import sys
import concurrent.futures

import numpy as np
import pytest

import flexmb

LENGTHS = [0.5, 1.0, 2.0, 4.0]
MASSES = [1.0, 2.0]
R_BOB = 0.02  # the pendulum file's bob radius


def pendulum_sweep(models, executor, **extra):
    """16 variants: 4 lengths × 2 masses × 2 integrators, to the first quarter period and a bit."""
    return flexmb.sweep(
        models / "pendulum.toml",
        {"L": LENGTHS, "m_bob": MASSES},
        integrators=["bdf", "adams"],
        outputs={"quarter_period": ("pivot_angle", "first_zero"), "angle_end": "pivot_angle", "energy_max": ("energy.total", "max")},
        t_end=1.2,
        rtol=1e-9,
        atol=1e-9,
        executor=executor,
        **extra,
    )


@pytest.fixture(scope="module")
def serial(models):
    return pendulum_sweep(models, "serial")


def same_value(a, b):
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (math.isnan(a) and math.isnan(b))
    return a == b


def without_wall_time(summary):
    summary = dict(summary)
    summary["statistics"] = {k: v for k, v in summary["statistics"].items() if k != "wall_time_s"}
    return summary


def assert_same_sweep(swept, serial):
    """Every column but the wall time equal to the last bit, and every run's results too."""
    assert swept.columns == serial.columns
    assert len(swept) == len(serial) == 16
    for row, expected in zip(swept.rows, serial.rows):
        for name in serial.columns:
            if name != "wall_time":
                assert same_value(row[name], expected[name]), (name, row, expected)
    for results, expected in zip(swept.results, serial.results):
        assert results.columns == expected.columns
        assert np.array_equal(results.values, expected.values)
        assert without_wall_time(results.summary) == without_wall_time(expected.summary)


def test_the_variants_are_the_grid_of_the_parameters_times_the_integrators(serial):
    assert serial.columns == ["variant", "L", "m_bob", "integrator", "wall_time", "steps", "newton_iterations", "rejected_steps", "quarter_period", "angle_end", "energy_max", "failure"]
    assert serial.column("variant") == list(range(16))
    assert serial.column("L") == [L for L in LENGTHS for _ in range(4)]
    assert serial.column("m_bob") == [m for _ in LENGTHS for m in MASSES for _ in range(2)]
    assert serial.column("integrator") == ["bdf", "adams"] * 8
    assert serial.failures == []
    assert all(row["steps"] > 0 and row["wall_time"] > 0 for row in serial.rows)
    # The BDF solves a Newton iteration per step; the Adams method here has none (explicit).
    assert all(row["newton_iterations"] >= row["steps"] if row["integrator"] == "bdf" else row["newton_iterations"] == 0 for row in serial.rows)
    # Each run's results are the model's with those parameters.
    assert serial.results[5].summary["settings"]["integrator"] == "adams"
    assert serial.results[5].summary["model"] == "pendulum"


def test_a_sweep_on_local_processes_equals_the_serial_run(serial, models):
    assert_same_sweep(pendulum_sweep(models, None), serial)


def test_a_sweep_on_a_local_ray_instance_equals_the_serial_run(serial, models):
    ray = pytest.importorskip("ray", reason="ray is not installed (pip install ray): the Ray sweep is not tested")
    ray.init(num_cpus=2, include_dashboard=False, logging_level="ERROR", log_to_driver=False)
    try:
        assert_same_sweep(pendulum_sweep(models, "ray"), serial)
        assert_same_sweep(pendulum_sweep(models, ray), serial)
    finally:
        ray.shutdown()


def test_any_concurrent_futures_executor_can_run_a_sweep(serial, models):
    with concurrent.futures.ThreadPoolExecutor(max_workers=2) as pool:
        assert_same_sweep(pendulum_sweep(models, pool), serial)


def test_the_period_grows_as_the_square_root_of_the_length_and_does_not_depend_on_the_mass(serial):
    # A physical pendulum (a point mass on a massless rod, the bob a sphere of radius r) released from
    # rest at 60°: T = 4 √(I / (m g L)) K(sin 30°), I = m (L² + 0.4 r²). The first zero of the angle is
    # T/4, so T/4 · √(L / (L² + 0.4 r²)) is the same for every length and mass: within 1e-6, the
    # error of locating the zero by linear interpolation between output rows 0.01 s apart (measured
    # spread 7.8e-7); the mass changes it by the integration's error only (measured 5e-9 at rtol 1e-9).
    quarter = np.array(serial.column("quarter_period"))
    length = np.array(serial.column("L"))
    scaled = quarter * np.sqrt(length / (length**2 + 0.4 * R_BOB**2))
    assert np.ptp(scaled) < 1e-6 * scaled.mean(), scaled
    by_mass = scaled.reshape(len(LENGTHS), len(MASSES), 2)
    assert np.abs(by_mass[:, 0, :] - by_mass[:, 1, :]).max() < 1e-7 * scaled.mean(), by_mass
    # The closed form: K(k) by the arithmetic-geometric mean, k = sin 30°.
    a, b = 1.0, math.sqrt(1 - 0.25)
    for _ in range(10):
        a, b = (a + b) / 2, math.sqrt(a * b)
    expected = math.pi / (2 * a) / math.sqrt(9.81)
    assert abs(scaled.mean() - expected) < 1e-6 * expected  # measured 5.4e-8
    # The energy does not grow (conservative, rtol 1e-9): its largest value is the initial one.
    for row in serial.rows:
        initial = -row["m_bob"] * 9.81 * row["L"] * math.cos(math.pi / 3)
        assert abs(row["energy_max"] - initial) < 1e-6 * abs(initial), row


def test_a_failing_variant_fills_the_failure_column_and_the_others_complete(models):
    swept = flexmb.sweep(models / "pendulum.toml", {"m_bob": [1.0, -1.0, 2.0]}, t_end=0.2, outputs=["pivot_angle"], executor=None, workers=2)
    assert swept.failures == [1]
    failure = swept.column("failure")[1]
    assert "mass must be positive and finite, got -1" in failure and "pendulum.toml:" in failure
    assert swept.results[1] is None and math.isnan(swept.rows[1]["pivot_angle"]) and math.isnan(swept.rows[1]["steps"])
    for k in (0, 2):
        assert swept.rows[k]["failure"] is None
        assert swept.rows[k]["pivot_angle"] == swept.results[k]["pivot_angle"][-1]
    # An output column the model does not have fails every variant, saying which columns there are.
    swept = flexmb.sweep(models / "pendulum.toml", {"L": [1.0]}, t_end=0.1, outputs={"x": ("no.such.column", "max")}, executor="serial")
    assert swept.failures == [0] and "no output column 'no.such.column'" in swept.rows[0]["failure"]


def test_zip_pairs_the_values_and_wrong_requests_are_refused(models):
    assert flexmb.sweep.__module__ == "flexmb.sweep"
    from flexmb.sweep import variants

    assert variants({"a": [1, 2], "b": [3, 4]}, ["bdf"], design="zip") == [({"a": 1.0, "b": 3.0}, "bdf"), ({"a": 2.0, "b": 4.0}, "bdf")]
    assert len(variants({"a": [1, 2], "b": [3, 4, 5]}, ["bdf", "adams"])) == 12
    with pytest.raises(ValueError, match="as many values for every parameter"):
        variants({"a": [1, 2], "b": [3]}, ["bdf"], design="zip")
    path = models / "pendulum.toml"
    with pytest.raises(ValueError, match="unknown reduction 'median'"):
        flexmb.sweep(path, {"L": [1.0]}, outputs={"x": ("pivot_angle", "median")})
    with pytest.raises(ValueError, match="executor must be"):
        flexmb.sweep(path, {"L": [1.0]}, executor="threads")


def test_asking_for_ray_without_ray_says_how_to_install_it(models, monkeypatch):
    monkeypatch.setitem(sys.modules, "ray", None)  # `import ray` raises ImportError
    with pytest.raises(ImportError, match="executor='ray' needs Ray: pip install ray"):
        flexmb.sweep(models / "pendulum.toml", {"L": [1.0]}, executor="ray")


def test_results_pickle_to_the_same_values_bit_for_bit(serial):
    results = serial.results[0]
    again = pickle.loads(pickle.dumps(results))
    assert again.columns == results.columns and again.units == results.units
    assert np.array_equal(again.values, results.values) and again.summary == results.summary


def test_workers_that_need_the_same_fe_reduction_share_one_cached_body(models, tmp_path):
    # The door in a fresh directory: its FE model is not reduced yet when four workers load it at
    # once; they reduce it once (the cache's lock), and their runs equal the serial ones.
    for name in ("door.toml", "door_fe.toml"):
        (tmp_path / name).write_text((models / "door" / name).read_text())
    door = tmp_path / "door.toml"
    parallel = flexmb.sweep(door, {"tilt_deg": [1.0, 2.0, 3.0, 4.0]}, t_end=0.05, outputs={"x": "door.node11.position.x"}, workers=4)
    cache = sorted(p.name for p in (tmp_path / ".flexmb-cache").iterdir())
    assert len(cache) == 1 and cache[0].startswith("door_fe-4N5S-orthonormal-") and cache[0].endswith(".json"), cache
    serial = flexmb.sweep(door, {"tilt_deg": [1.0, 2.0, 3.0, 4.0]}, t_end=0.05, outputs={"x": "door.node11.position.x"}, executor="serial")
    assert parallel.failures == [] and parallel.column("x") == serial.column("x")
    for a, b in zip(parallel.results, serial.results):
        assert np.array_equal(a.values, b.values)
