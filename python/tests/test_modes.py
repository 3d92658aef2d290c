"""flexmb.modes: the preprocessor of `flexmb modes` from Python — the program's frequencies and mass
properties to the digits it prints, the cantilever's bending frequency against Euler–Bernoulli's
closed form converging with the mesh, mode shapes with node ids, and the flexible-body file it writes
read back by a model."""

import math
import re

import numpy as np
import pytest

import flexmb

# models/fe/cantilever.toml: steel (E 210 GPa, ρ 7850 kg/m³), 1 m long, 20 mm (along y) by 10 mm
# (along z), clamped at x = 0, 20 beam elements, mass lumped with rotary inertia, [modes] 4N2S.
E, RHO, LENGTH, WIDTH, HEIGHT = 210e9, 7850.0, 1.0, 0.020, 0.010
BETA_1 = 1.8751040687119611  # first root of cos βL cosh βL = −1


def euler_bernoulli_first_frequency(second_moment):
    area = WIDTH * HEIGHT
    return BETA_1**2 / (2 * math.pi * LENGTH**2) * math.sqrt(E * second_moment / (RHO * area))


def printed_table(report):
    """The rows of the program's frequency table: label → (FE f text, reduced f text)."""
    rows = re.findall(r"^\s+\d+\s+(\w+)\s+\w+\s+\S+\s+(\S+)\s+(\S+)$", report, flags=re.M)
    return {label: (fe, reduced) for label, fe, reduced in rows}


def test_frequencies_and_mass_properties_are_the_programs_to_the_digits_printed(models, program, tmp_path):
    body = flexmb.modes(models / "fe" / "cantilever.toml")
    report = program("modes", models / "fe" / "cantilever.toml", "--out", tmp_path / "cantilever.json").stdout
    table = printed_table(report)
    assert list(table) == body.labels == ["O1", "O2", "O3", "O4", "O5", "O6"]
    assert body.mode_set == "4N2S" and body.basis == "orthonormal" and body.mass_model == "lumped"
    for k, label in enumerate(body.labels):
        assert table[label] == (f"{body.fe_frequencies[k]:.6f}", f"{body.frequencies[k]:.6f}")
    mass = float(re.search(r"mass (\S+) kg", report).group(1))
    assert f"{body.mass:.6e}" == f"{mass:.6e}"
    com = [float(x) for x in re.search(r"centre of mass \[(.*?)\]", report).group(1).split(",")]
    assert [f"{x:.6f}" for x in body.center_of_mass] == [f"{x:.6f}" for x in com]
    printed = dict(re.findall(r"(I[xyz]{2}) ([-+.e0-9]+)", report))
    for name, (r, c) in {"Ixx": (0, 0), "Iyy": (1, 1), "Izz": (2, 2)}.items():
        assert f"{body.inertia[r, c]:.6e}" == f"{float(printed[name]):.6e}", name
    # The closed forms of a slender bar: ρ A L and, about its centre, ρ A L³ / 12 across it.
    assert body.mass == pytest.approx(RHO * WIDTH * HEIGHT * LENGTH, rel=1e-12)
    assert body.center_of_mass == pytest.approx([LENGTH / 2, 0, 0], abs=1e-12)
    # The file the program wrote is the one write() writes.
    body.write(tmp_path / "from_python.json")
    assert (tmp_path / "from_python.json").read_text() == (tmp_path / "cantilever.json").read_text()


def test_the_first_bending_frequency_converges_to_euler_bernoulli(models, tmp_path):
    # The first mode bends across the thin side (deflection along z): I = w h³ / 12.
    exact = euler_bernoulli_first_frequency(WIDTH * HEIGHT**3 / 12)
    text = (models / "fe" / "cantilever.toml").read_text()
    errors = []
    for elements in (10, 20, 40):
        path = tmp_path / f"cantilever_{elements}.toml"
        path.write_text(text.replace("elements = 20", f"elements = {elements}"))
        body = flexmb.modes(path, modes="2N", basis="raw")
        errors.append(abs(body.fe_frequencies[0] - exact) / exact)
        assert body.frequencies[0] == pytest.approx(body.fe_frequencies[0], rel=1e-10)
    print("relative errors of f1 for 10, 20, 40 elements:", ", ".join(f"{e:.2e}" for e in errors))
    assert errors[1] < 2e-3, errors  # 20 elements, as shipped: within 0.2 %
    # Halving the elements' length divides the error by about 4 (second order).
    assert 3.0 < errors[0] / errors[1] < 5.0 and 3.0 < errors[1] / errors[2] < 5.0, errors
    # The second mode bends across the wide side: I = h w³ / 12, twice the frequency.
    exact_2 = euler_bernoulli_first_frequency(HEIGHT * WIDTH**3 / 12)
    assert body.fe_frequencies[1] == pytest.approx(exact_2, rel=errors[2] * 1.5)


def test_mode_shapes_with_node_ids(models):
    body = flexmb.modes(models / "fe" / "cantilever.toml", modes="4N", basis="raw")
    assert body.labels == ["N1", "N2", "N3", "N4"] and body.kinds == ["vibration"] * 4
    shapes, ids, positions = body.mode_shapes, body.node_ids, body.node_positions
    assert shapes.shape == (21, 6, 4) and ids.shape == (21,) and positions.shape == (21, 3)
    assert sorted(ids.tolist()) == list(range(1, 22))
    clamped = int(np.argmin(positions[:, 0]))
    tip = int(np.argmax(positions[:, 0]))
    assert np.all(shapes[clamped] == 0.0), "the clamped node does not move"
    # N1 bends along z (translation z, rotation about y), N2 along y; the tip moves most.
    assert abs(shapes[tip, 2, 0]) == np.abs(shapes[:, 2, 0]).max() > 0
    assert np.abs(shapes[:, [0, 1, 3, 5], 0]).max() < 1e-9 * np.abs(shapes[:, 2, 0]).max()
    assert np.abs(shapes[:, 1, 1]).max() > 0 and np.abs(shapes[:, 2, 1]).max() < 1e-9 * np.abs(shapes[:, 1, 1]).max()
    # Generalized mass and stiffness: ω² = k / m for each vibration mode.
    omega = 2 * math.pi * body.frequencies
    assert np.diag(body.modal_stiffness) / np.diag(body.modal_mass) == pytest.approx(omega**2, rel=1e-9)


def test_the_written_file_loads_as_a_flexible_body_with_the_same_frequencies(models, tmp_path):
    path = tmp_path / "beam.json"
    body = flexmb.modes(models / "fe" / "cantilever.toml", modes="4N2S", path=path)
    m = flexmb.ModelBuilder("cantilever_on_a_hinge", gravity=[0, -9.81, 0], base_dir=tmp_path)
    m.flexible_body("beam", body_file="beam.json")
    m.marker("hinge_ground", body="ground")
    m.marker("hinge_beam", body="beam", node=1)
    m.joint("hinge", type="revolute", i="hinge_ground", j="hinge_beam")
    check = m.build().check()
    loaded = check["flexible_bodies"][0]
    assert loaded["modes"] == body.labels and loaded["nodes"] == 21
    assert loaded["frequencies_hz"] == body.frequencies.tolist()
    assert check["degrees_of_freedom"] == 1 + 6


def test_bad_arguments_raise_the_programs_messages(models, tmp_path):
    with pytest.raises(flexmb.ModelError, match=r"modes: mode set `4X`"):
        flexmb.modes(models / "fe" / "cantilever.toml", modes="4X")
    with pytest.raises(flexmb.ModelError, match=r"asked for 300 vibration modes"):
        flexmb.modes(models / "fe" / "cantilever.toml", modes="300N")
    with pytest.raises(flexmb.ModelError, match=r'basis: expected "raw" or "orthonormal", got "orthogonal"'):
        flexmb.modes(models / "fe" / "cantilever.toml", basis="orthogonal")
    bare = tmp_path / "bare.toml"
    bare.write_text((models / "fe" / "cantilever.toml").read_text().replace('set = "4N2S"', ""))
    with pytest.raises(flexmb.ModelError, match=r"bare.toml: no mode set: give modes="):
        flexmb.modes(bare)
    with pytest.raises(flexmb.ModelError, match=r"cannot read the FE model file"):
        flexmb.modes(tmp_path / "missing.toml")


def test_stresses_are_stored_when_asked_and_the_root_stress_of_the_tip_load_mode_is_beam_theory_s(models, tmp_path):
    # The static correction mode of the 1 N tip force along z (S1, raw basis): its root stress over its
    # tip deflection is beam theory's σ/δ = (P L c / I) / (P L³ / 3 E I) = 3 E c / L², whatever the
    # mode's scale (Hermite beams are exact for an end load). Without stresses= the file has none.
    import json

    plain = tmp_path / "plain.json"
    flexmb.modes(models / "fe" / "cantilever.toml", modes="4N2S", basis="raw", path=plain)
    assert "stresses" not in json.loads(plain.read_text())
    path = tmp_path / "stressed.json"
    flexmb.modes(models / "fe" / "cantilever.toml", modes="4N2S", basis="raw", path=path, stresses=True)
    data = json.loads(path.read_text())
    labels = [mode["label"] for mode in data["modes"]]
    s1 = labels.index("S1")
    x = np.array([node["position"][0] for node in data["nodes"]])
    root, tip = int(np.argmin(x)), int(np.argmax(x))
    deflection = data["shapes"][s1]["translation"][tip][2]
    stresses = data["stresses"]
    at_root = [k for k, node in enumerate(stresses["nodes"]) if node == root]
    assert at_root, "stress points at the root"
    sigma_xx = max(abs(stresses["modes"][s1][k][0]) for k in at_root)
    assert sigma_xx / abs(deflection) == pytest.approx(3 * E * (HEIGHT / 2) / LENGTH**2, rel=1e-6)
