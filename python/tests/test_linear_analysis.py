"""Model.linearize and Model.eigen: the pendulum's closed-form state space and the tilting rotor's
closed-form whirl, as numpy arrays, and bad requests raising ModelError with the program's message."""

import math

import numpy as np
import pytest

import flexmb
from conftest import REPOSITORY

MODELS = "crates/flexmb-cli/tests/models/linear_analysis"


def test_a_hanging_pendulum_linearizes_to_its_closed_form():
    model = flexmb.load(REPOSITORY / MODELS / "hanging_pendulum.toml")
    linear = model.linearize(inputs=["drive.z"], outputs=["pivot_angle"])
    mass, stiffness = 0.02 + 1.5 * 0.8**2, 1.5 * 9.81 * 0.8
    assert linear["coordinates"] == ["pendulum.theta.z"]
    assert linear["M"][0, 0] == pytest.approx(mass, rel=1e-12)
    assert linear["K"][0, 0] == pytest.approx(stiffness, rel=1e-9)
    space = linear["state_space"]
    np.testing.assert_allclose(space["A"], [[0.0, 1.0], [-stiffness / mass, 0.0]], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(space["B"], [[0.0], [1.0 / mass]], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(space["C"], [[1.0, 0.0]], atol=1e-9)


def test_a_tilting_rotor_whirls_at_the_closed_form_frequencies():
    modes = flexmb.load(REPOSITORY / MODELS / "tilting_rotor.toml").eigen()
    it, ip, ktheta, spin = 0.03, 0.035, 2 * 2.0e4 * 0.1**2, 300.0
    root = math.sqrt(ip**2 * spin**2 + 4 * it * ktheta)
    backward, forward = (root - ip * spin) / (2 * it) / (2 * math.pi), (root + ip * spin) / (2 * it) / (2 * math.pi)
    f = modes["frequencies"]
    assert f[0] == pytest.approx(backward, rel=1e-7) and f[2] == pytest.approx(forward, rel=1e-7)
    assert modes["whirl"] == ["backward", "none", "forward"]
    assert modes["shapes"].dtype == np.complex128 and modes["shapes"].shape == (3, len(modes["velocity_names"]))
    assert np.abs(modes["shapes"]).max(axis=1) == pytest.approx(1.0)


def test_bad_requests_raise_model_error():
    model = flexmb.load(REPOSITORY / MODELS / "hanging_pendulum.toml")
    with pytest.raises(flexmb.ModelError, match="input 'motor' is not a force element or driver"):
        model.linearize(inputs=["motor"])
