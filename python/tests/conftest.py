"""Shared fixtures: the repository's models, and the `flexmb` program to compare the package with."""

import os
import pathlib
import shutil
import subprocess

import pytest

REPOSITORY = pathlib.Path(__file__).resolve().parents[2]
MODELS = REPOSITORY / "models"


@pytest.fixture(scope="session")
def models():
    """The folder of the shipped example models."""
    return MODELS


def program_path():
    """The `flexmb` program: $FLEXMB_PROGRAM, else the release build of this checkout, else on PATH."""
    given = os.environ.get("FLEXMB_PROGRAM")
    if given:
        return pathlib.Path(given)
    built = REPOSITORY / "target" / "release" / "flexmb"
    if built.exists():
        return built
    found = shutil.which("flexmb")
    return pathlib.Path(found) if found else None


@pytest.fixture(scope="session")
def program():
    """Runs the `flexmb` program with the given arguments; returns the completed process (text output)."""
    path = program_path()
    if path is None:
        pytest.skip("the flexmb program is not built: cargo build --release -p flexmb-cli (or set FLEXMB_PROGRAM)")

    def run(*arguments, check=True):
        done = subprocess.run([str(path), *map(str, arguments)], capture_output=True, text=True)
        if check and done.returncode != 0:
            raise AssertionError(f"flexmb {' '.join(map(str, arguments))} failed:\n{done.stdout}\n{done.stderr}")
        return done

    return run


def read_csv_text(path):
    """A result CSV as its header and its rows of value texts, as written."""
    lines = pathlib.Path(path).read_text().splitlines()
    return lines[0].split(","), [line.split(",") for line in lines[1:]]
