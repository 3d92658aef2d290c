"""Type stubs of the flexmb package (its native module, flexmb._native, re-exported)."""

import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Path = Union[str, "os.PathLike[str]"]

class ModelError(ValueError):
    """A model file that cannot be read, parsed, validated, built or assembled, or run settings that
    cannot be used; the message is the command line's (file, key path, line)."""

class SimulationError(RuntimeError):
    """A simulation that failed after it started; the message is the command line's, and ``results``
    holds the output rows computed before the failure."""

    results: "Results"

def load(
    path: _Path,
    parameters: Optional[Mapping[str, float]] = None,
    modes: Optional[Mapping[str, str]] = None,
) -> "Model":
    """Loads the model file at ``path``, with ``parameters`` (name → value) replacing the values of its
    ``[parameters]`` table and ``modes`` (flexible body → mode set, e.g. ``"4N5S"``) the mode sets of its
    flexible bodies, as a study's variants do. Raises ``ModelError`` with the command line's message."""

class Model:
    """A mechanism loaded from a model file, with the file's ``[simulation]`` values as the defaults of
    its runs."""

    @property
    def name(self) -> str:
        """The model's name."""
    @property
    def file(self) -> str:
        """The model file, as given to ``load``."""
    @property
    def parameters(self) -> Dict[str, float]:
        """The parameters (name → value) as loaded, overrides applied."""
    @property
    def columns(self) -> List[str]:
        """The output column names of a run, ``t`` first, as in the result CSV of ``flexmb run``."""
    @property
    def defaults(self) -> Dict[str, float]:
        """The file's ``[simulation]`` values: ``t_end``, ``output_step``, ``rtol``, ``atol``."""
    def check(self) -> Dict[str, Any]:
        """Assembles the initial state and runs the velocity analysis, as ``flexmb check`` does. Keys:
        ``model``, ``degrees_of_freedom``, ``redundant_constraints`` (descriptions), ``bodies``,
        ``joints``, ``force_elements`` (names), ``markers``, ``constraint_equations``, ``assembly``
        (``iterations``, ``initial_residual``, ``residual``), ``velocity_adjustments``,
        ``flexible_bodies`` (``name``, ``mode_set``, ``basis``, ``modes``, ``frequencies_hz``, ``nodes``,
        ``warnings``). Raises ``ModelError`` when the model cannot be assembled."""
    def simulate(
        self,
        t_end: Optional[float] = None,
        integrator: Optional[str] = None,
        rtol: Optional[float] = None,
        atol: Optional[float] = None,
        output_step: Optional[float] = None,
        spectral_radius: Optional[float] = None,
    ) -> "Results":
        """Simulates from the initial state to ``t_end``; ``None`` takes the model file's value;
        ``integrator`` is ``"bdf"``, ``"adams"`` or ``"gen-alpha"`` (``spectral_radius`` ρ∞, default 0.9).
        Runs without the GIL; Ctrl-C raises ``KeyboardInterrupt`` after the current step, with the rows so
        far in its ``results`` attribute; a failure raises ``SimulationError``."""
    def simulation(
        self,
        t_end: Optional[float] = None,
        integrator: Optional[str] = None,
        rtol: Optional[float] = None,
        atol: Optional[float] = None,
        output_step: Optional[float] = None,
        spectral_radius: Optional[float] = None,
    ) -> "Simulation":
        """A ``Simulation`` that steps on request, with the arguments of ``simulate``."""
    def with_law(
        self,
        name: str,
        law: Union[Callable[[float, npt.NDArray[np.float64]], float], Callable[[float], Tuple[float, float, float]]],
        measures: Sequence[str] = (),
        component: Optional[str] = None,
    ) -> "Model":
        """A copy of the model whose force element or driver ``name`` takes its law from the Python
        callable ``law`` (Python in the loop). A force element's law is ``law(t, measures) -> float``,
        ``measures`` a numpy array of the values of the measures named in ``measures``, in that order:
        the actuator of a spring-damper, or the ``component`` (``"x"``, ``"y"``, ``"z"``) of an applied
        force or torque. A driver's law is ``law(t) -> (f, f', f'')``, the motion with its first two
        time derivatives. An exception in the law stops the run with ``SimulationError``, the exception
        its ``__cause__``. Raises ``ModelError`` for an unknown element, driver or measure."""
    @property
    def laws(self) -> List[str]:
        """The names of the laws given as Python callables (``with_law``), force elements then drivers."""

class Results:
    """The outputs of a run: ``time`` and every column as numpy arrays by name (``results["tip.x"]``),
    the column names and units, the statistics and the summary."""

    @property
    def time(self) -> npt.NDArray[np.float64]:
        """The output times (s): the column ``t``."""
    @property
    def columns(self) -> List[str]:
        """The column names, ``t`` first."""
    @property
    def units(self) -> List[str]:
        """The unit of each column, in the order of ``columns``."""
    @property
    def values(self) -> npt.NDArray[np.float64]:
        """All values, a row per output time and a column per name of ``columns``."""
    @property
    def summary(self) -> Dict[str, Any]:
        """The JSON summary ``flexmb run`` writes (status, settings, statistics, assembly, residuals,
        energy, physics checks, warnings, columns), as a dict."""
    @property
    def stats(self) -> Dict[str, Any]:
        """The summary's ``statistics``: steps, rejected steps, error-test and Newton failures, Newton
        iterations, residual and Jacobian evaluations, matrix factorizations, RMS step, wall time."""
    def __getitem__(self, name: str) -> npt.NDArray[np.float64]:
        """The column ``name``, one value per output time; ``KeyError`` naming the columns otherwise."""
    def __contains__(self, name: str) -> bool:
        """Whether there is a column ``name``."""
    def __len__(self) -> int:
        """The number of rows (output times)."""
    def to_pandas(self) -> Any:
        """The results as a ``pandas.DataFrame``; ``ImportError`` when pandas is not installed."""

class Simulation:
    """A simulation that steps on request, its outputs collected in ``results``, its state read between
    calls, saved as a checkpoint (``save``) and resumed (``Simulation.resume``)."""

    @staticmethod
    def resume(
        model: Model,
        path: _Path,
        t_end: Optional[float] = None,
        integrator: Optional[str] = None,
        rtol: Optional[float] = None,
        atol: Optional[float] = None,
        output_step: Optional[float] = None,
        spectral_radius: Optional[float] = None,
    ) -> "Simulation":
        """Continues the simulation saved at ``path`` (by ``save`` or ``flexmb run --save-state``) of the
        same model file and integrator, to ``t_end``; its ``results`` hold the rows after the
        checkpoint's time. ``ModelError`` for a file that is not such a checkpoint."""
    def advance_to(self, t: float) -> float:
        """Steps until the time reaches ``t`` (the last step may end after it) or the end time; returns
        the time reached. Ctrl-C raises ``KeyboardInterrupt`` and leaves the simulation usable."""
    def run(self) -> Results:
        """Steps to the end time and returns ``results``."""
    @property
    def time(self) -> float:
        """The time of the last accepted step (s)."""
    @property
    def t_end(self) -> float:
        """The end time (s)."""
    @property
    def finished(self) -> bool:
        """Whether the end time is reached and its outputs reported."""
    @property
    def positions(self) -> npt.NDArray[np.float64]:
        """The positions ``q`` at the last accepted step (per body: origin, Euler parameters, modal
        coordinates)."""
    @property
    def velocities(self) -> npt.NDArray[np.float64]:
        """The velocities ``v`` at the last accepted step (per body: origin velocity, body-frame angular
        velocity, modal rates)."""
    @property
    def results(self) -> Results:
        """The outputs reported since the simulation was started or resumed, with the summary so far."""
    def save(self, path: _Path) -> None:
        """Writes the simulation's complete state to ``path`` as the checkpoint of
        ``flexmb run --save-state``."""
    def set_state(
        self,
        positions: Optional[npt.ArrayLike] = None,
        velocities: Optional[npt.ArrayLike] = None,
    ) -> Dict[str, float]:
        """Replaces the positions and/or velocities (``None`` keeps them) at the current time: the
        positions moved onto the constraints by the assembly's Newton iteration, the velocities projected
        onto the velocity constraints (both the least change), the integrator restarted there (order 1,
        a new first step). Returns ``assembly_iterations``, ``position_change``, ``velocity_change``,
        ``position_residual``, ``velocity_residual`` and ``energy_change``. Raises ``ValueError`` for a
        wrong length (naming the expected one) or a value that is not finite."""
    @property
    def coordinate_names(self) -> Dict[str, List[str]]:
        """``{"positions": [...], "velocities": [...]}``: a name for each entry of ``positions``
        (``<body>.R.x``, ``<body>.p.0``, ``<body>.a.1``) and of ``velocities`` (``<body>.Rdot.x``,
        ``<body>.omega.x`` in body axes, ``<body>.adot.1``)."""
