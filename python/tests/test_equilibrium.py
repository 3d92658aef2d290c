"""Model.equilibrium against the closed form: the shipped pendulum, released 60° from hanging, has its
static equilibrium hanging below the pivot, the pivot carrying the bob's weight; the robot arm's motor
holds the flexible link with the torque of its weight."""

from pathlib import Path

import numpy as np
import pytest

import flexmb

REPOSITORY = Path(__file__).resolve().parents[2]


def test_pendulum_hangs_at_its_equilibrium_and_the_pivot_carries_its_weight():
    model = flexmb.load(REPOSITORY / "models" / "pendulum.toml", parameters={"m_bob": 2.0})
    eq = model.equilibrium()
    assert eq["force_residual"] <= eq["force_tolerance"]
    assert eq["outputs"]["pivot_angle"] == pytest.approx(0.0, abs=1e-9)
    on_pendulum = [r for r in eq["reactions"] if r["joint"] == "pivot" and r["body"] == "pendulum"]
    assert len(on_pendulum) == 1
    np.testing.assert_allclose(on_pendulum[0]["force"], [0.0, 2.0 * 9.81, 0.0], atol=1e-8)
    assert eq["degrees_of_freedom"] == 1 and eq["unstable_directions"] == 0
    assert len(eq["positions"]) == len(eq["position_names"])


def test_a_free_motion_is_named():
    builder = flexmb.ModelBuilder("falling", gravity=[0.0, 0.0, -9.81])
    builder.body("ball", mass=1.0, inertia=[0.1, 0.1, 0.1])
    with pytest.raises(flexmb.ModelError, match=r"ball.*translation along -z"):
        builder.build().equilibrium()
