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
    def equilibrium(self, t: Optional[float] = None) -> Dict[str, Any]:
        """The static equilibrium at ``t`` (default the start time), as ``flexmb equilibrium``: keys
        ``positions``, ``position_names``, ``multipliers``, ``reactions`` (per joint side: ``joint``,
        ``body``, ``marker``, ``point``, ``force``, ``torque``), ``outputs`` (column → value),
        ``iterations``, ``method``, residuals, ``history``, ``degrees_of_freedom``,
        ``neutral_directions``, ``unstable_directions``, ``t``. Raises ``ModelError`` naming a free motion."""
    def linearize(
        self,
        at: Optional[str] = None,
        t: Optional[float] = None,
        inputs: Optional[List[str]] = None,
        outputs: Optional[List[str]] = None,
    ) -> Dict[str, Any]:
        """Linearizes at an operating point (``at="initial"``, the assembled initial state with its
        velocities; ``at="equilibrium"``; or ``t``, the state a simulation reaches at that time). Keys:
        ``M``, ``C``, ``K`` (numpy, independent coordinates), ``basis`` (velocity coordinates ×
        independent coordinates), ``coordinates``, ``velocity_names``, ``t``; with ``inputs`` (force
        elements: ``NAME.x``/``.y``/``.z`` of an applied force or torque, ``NAME`` of a spring-damper;
        drivers: ``NAME``, ``NAME.rate``, ``NAME.acceleration`` for the offset of an angle or displacement
        driver) or
        ``outputs`` (measures), ``state_space``: ``A``, ``B``, ``C``, ``D``, ``states``, ``inputs``,
        ``outputs``. As ``flexmb linearize``; raises ``ModelError``."""
    def eigen(self, at: Optional[str] = None, t: Optional[float] = None) -> Dict[str, Any]:
        """Eigen-analysis at an operating point (as ``linearize``). Keys: ``frequencies`` (Hz, undamped
        natural), ``damped_frequencies``, ``damping_ratios``, ``eigenvalues`` (complex), ``whirl``
        (``"forward"``, ``"backward"``, ``"none"``), ``rigid_body``, ``shapes`` (complex, modes ×
        velocity coordinates), ``velocity_names``, ``coordinates``, ``t``. As ``flexmb eigen``; raises
        ``ModelError``."""
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
    the column names and units, the statistics and the summary. Results pickle (for process pools and
    Ray) to the same values, bit for bit."""

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

# Models built in code and the preprocessor.

def loads(
    text: str,
    source: str = "<string>",
    base_dir: Optional[_Path] = None,
    parameters: Optional[Mapping[str, float]] = None,
    modes: Optional[Mapping[str, str]] = None,
) -> Model:
    """Loads a model from ``text``, the text of a model file: ``source`` names it in messages, relative
    ``fe_model`` and ``body_file`` paths start at ``base_dir`` (default the current directory);
    ``parameters`` and ``modes`` as in ``load``. Raises ``ModelError``."""

class ModelBuilder:
    """A model built in code: one call per table of a model file, the keywords its keys; ``build()``
    loads the text of ``to_toml()`` with the model file's validation and messages."""

    name: str
    base_dir: Optional[_Path]
    def __init__(self, name: str, gravity: Optional[Any] = None, base_dir: Optional[_Path] = None) -> None:
        """A builder of the model ``name`` with ``gravity`` (m/s²) if given."""
    def parameter(self, name: str, value: Union[float, str]) -> "ModelBuilder":
        """``[parameters] name = value``."""
    def simulation(self, **keys: Any) -> "ModelBuilder":
        """``[simulation]``: ``t_end``, ``output_step``, ``rtol``, ``atol``, ``integrator``, …"""
    def body(self, name: str, **keys: Any) -> "ModelBuilder":
        """``[[body]]``: a rigid body."""
    def flexible_body(self, name: str, **keys: Any) -> "ModelBuilder":
        """``[[flexible_body]]``: from an FE model file (``fe_model``) or a flexible-body file (``body_file``)."""
    def marker(self, name: str, **keys: Any) -> "ModelBuilder":
        """``[[marker]]``: a frame fixed on a body."""
    def joint(self, name: str, **keys: Any) -> "ModelBuilder":
        """``[[joint]]``: ``type`` between markers ``i`` and ``j``."""
    def driver(self, name: str, **keys: Any) -> "ModelBuilder":
        """``[[driver]]``: a prescribed motion."""
    def measure(self, name: str, **keys: Any) -> "ModelBuilder":
        """``[[measure]]``: a named quantity."""
    def force(self, name: str, **keys: Any) -> "ModelBuilder":
        """``[[force]]``: a force element."""
    def output(self, type: Optional[str] = None, **keys: Any) -> "ModelBuilder":
        """``[[output]]``: what a run reports."""
    def to_toml(self) -> str:
        """The model file this builder describes, as text."""
    def build(
        self,
        parameters: Optional[Mapping[str, float]] = None,
        modes: Optional[Mapping[str, str]] = None,
    ) -> Model:
        """The ``Model`` of this builder; raises ``ModelError`` with the file's message and the builder
        call that made the table it names."""

def modes(
    fe_model: _Path,
    modes: Optional[str] = None,
    basis: Optional[str] = None,
    mass: Optional[str] = None,
    solver: Optional[str] = None,
    path: Optional[_Path] = None,
    stresses: Optional[bool] = None,
) -> "FlexibleBody":
    """Reduces the FE model file ``fe_model`` to the mode set ``modes`` (e.g. ``"4N5S"``) as ``flexmb
    modes`` does; ``basis`` ``"raw"``/``"orthonormal"``, ``mass`` ``"lumped"``/``"consistent"``,
    ``solver`` ``"auto"``/``"dense"``/``"lanczos"``, ``stresses`` (store each mode's stresses, as
    ``flexmb modes --stresses``), each ``None`` taking the file's value; with ``path``, writes the
    flexible-body file there (without the file's ``mass``, consistent for beams and solids and lumped for
    shells). Raises ``ModelError``."""

class FlexibleBody:
    """A flexible body reduced from an FE model: modes, frequencies, shapes, mass properties, and its
    flexible-body file (``write``)."""

    name: str
    """The body's name."""
    mode_set: str
    """The mode set, e.g. ``"4N5S"``."""
    basis: str
    """``"raw"`` or ``"orthonormal"``."""
    mass_model: str
    """``"lumped"``, ``"consistent"`` or ``"mixed"`` (consistent beams or solids with lumped shells)."""
    labels: List[str]
    """The mode labels in basis order (``N1``, ``S1``, ``O1``, …)."""
    kinds: List[str]
    """Each mode's kind: ``"vibration"``, ``"static"`` or ``"orthonormal"``."""
    frequencies: npt.NDArray[np.float64]
    """Natural frequencies of the reduced body (Hz), ascending."""
    fe_frequencies: npt.NDArray[np.float64]
    """Lowest natural frequencies of the supported FE model (Hz), ascending."""
    node_ids: npt.NDArray[np.uint64]
    """The FE nodes' ids, in the order of ``node_positions`` and ``mode_shapes``."""
    node_positions: npt.NDArray[np.float64]
    """Nodes × 3: positions in the body frame (m)."""
    mode_shapes: npt.NDArray[np.float64]
    """Nodes × 6 × modes: translations x, y, z and rotations about x, y, z per unit modal coordinate."""
    mass: float
    """Mass of the undeformed body (kg)."""
    center_of_mass: npt.NDArray[np.float64]
    """Centre of mass in the body frame (m)."""
    inertia: npt.NDArray[np.float64]
    """3 × 3 inertia tensor about the centre of mass (kg m²)."""
    modal_mass: npt.NDArray[np.float64]
    """Modal mass matrix (modes × modes)."""
    modal_stiffness: npt.NDArray[np.float64]
    """Modal stiffness matrix (modes × modes)."""
    warnings: List[str]
    """The FE model's and the reduction's warnings."""
    seconds: float
    """Wall time of the reduction (s)."""
    def write(self, path: _Path) -> None:
        """Writes the flexible-body file (JSON), as ``flexmb modes --out`` does."""

# Sweeps (flexmb/sweep.py): a model's variants on local processes, a Ray cluster or serially.

class SweepResult:
    """What ``sweep`` gathered: ``rows`` (a dict per variant, in variant order), ``table`` (a pandas
    DataFrame when pandas is installed, else the rows), ``results`` (each variant's ``Results``; for a
    failed run the rows before the failure, or ``None`` when nothing ran), ``columns`` (the table's
    column names) and ``wall_time`` (the sweep's wall time, s)."""

    columns: List[str]
    rows: List[Dict[str, Any]]
    results: List[Optional[Results]]
    wall_time: float
    @property
    def table(self) -> Any:
        """The table as a pandas DataFrame if pandas can be imported, else the list of rows."""
    def column(self, name: str) -> List[Any]:
        """The values of the table's column ``name``, one per variant; ``KeyError`` otherwise."""
    @property
    def failures(self) -> List[int]:
        """The indices of the variants that failed."""
    def __len__(self) -> int:
        """The number of variants."""

def sweep(
    model: _Path,
    parameters: Mapping[str, Sequence[float]],
    integrators: Sequence[str] = ("bdf",),
    outputs: Union[None, Sequence[str], Mapping[str, Union[str, Tuple[str, str]]]] = None,
    t_end: Optional[float] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    output_step: Optional[float] = None,
    design: str = "grid",
    executor: Any = None,
    workers: Optional[int] = None,
) -> SweepResult:
    """Runs the model file in every variant (the ``design`` — ``"grid"``: every combination,
    ``"zip"``: the k-th values together — of the ``parameters`` × ``integrators``) on local processes
    (``executor=None``, ``workers`` of them, default the cores), on Ray (``"ray"`` or the ``ray``
    module, after ``ray.init(address=...)``), serially (``"serial"``) or on a
    ``concurrent.futures.Executor``; returns the table (variant, parameters, integrator, wall_time,
    steps, newton_iterations, rejected_steps, the ``outputs`` reduced by final, initial, min, max,
    max_abs, mean, time_of_min, time_of_max or first_zero, failure) and each run's results."""
