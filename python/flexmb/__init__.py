"""flexmb from Python: load a model file (with parameter overrides), check it, simulate it, and read
the outputs as numpy arrays; or step a simulation, read its state, save it and resume it.

    import flexmb
    model = flexmb.load("models/pendulum.toml", parameters={"L": 2.0})
    print(model.check()["degrees_of_freedom"])
    results = model.simulate(t_end=2.0)
    angle = results["pivot_angle"]          # numpy array, one value per results.time

The work is done by the Rust library that the ``flexmb`` program runs on: the same model files, the
same error messages (file, key path, line), the same results and summaries.
"""

from ._native import (
    Model,
    ModelError,
    Results,
    Simulation,
    SimulationError,
    __version__,
    load,
)

# Sweeps: a model's variants on local processes, a Ray cluster or serially (flexmb/sweep.py).
from .sweep import SweepResult, sweep

__all__ = ["Model", "ModelError", "Results", "Simulation", "SimulationError", "__version__", "load"]

# Models built in code (flexmb.ModelBuilder, through flexmb.loads) and the preprocessor (flexmb.modes).
from ._native import FlexibleBody, loads, modes
from .builder import ModelBuilder

__all__ += ["FlexibleBody", "ModelBuilder", "loads", "modes"]
__all__ += ["SweepResult", "sweep"]
