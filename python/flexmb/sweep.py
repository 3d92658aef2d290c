"""Sweeps: one model file run in many variants (parameter values × integrators) on local processes,
on a Ray cluster or one after the other, gathered into one table plus each run's results.

    import flexmb
    swept = flexmb.sweep("models/pendulum.toml", {"L": [0.5, 1.0, 2.0], "m_bob": [1.0, 2.0]},
                         integrators=["bdf", "adams"], t_end=2.0,
                         outputs={"quarter_period": ("pivot_angle", "first_zero")})
    print(swept.table)                  # a pandas DataFrame if pandas is installed
    swept.results[0]["pivot_angle"]     # the first variant's flexmb.Results

Each variant is a call of ``flexmb.load(model, parameters=...)`` and ``Model.simulate`` in a worker
that loads the model file itself: the workers share nothing but files (the model file, its FE model
files and their reduction cache, which is safe when many workers reduce the same FE model at once).
"""

import concurrent.futures
import itertools
import math
import os
import time
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from ._native import SimulationError, load

#: The reductions an output may ask for: a column's value at the end or at the start, its smallest,
#: largest, largest absolute and mean value over the output times, the time of its smallest and of its
#: largest value, and the time at which it first changes sign (interpolated linearly between rows).
REDUCTIONS = ("final", "initial", "min", "max", "max_abs", "mean", "time_of_min", "time_of_max", "first_zero")

#: The cost columns of a sweep's table, from each run's statistics.
COST_COLUMNS = ("wall_time", "steps", "newton_iterations", "rejected_steps")


class SweepResult:
    """What ``sweep`` gathered: ``rows`` (a dict per variant, in variant order), ``table`` (those rows
    as a pandas DataFrame when pandas is installed, else the list of dicts), ``results`` (each
    variant's ``flexmb.Results``; for a failed run the rows computed before it failed, or ``None``
    when nothing ran), ``columns`` (the table's column names, in order) and ``wall_time`` (the
    sweep's wall time in s, from the call to the gathered table)."""

    def __init__(self, columns: List[str], rows: List[Dict[str, Any]], results: List[Any], wall_time: float):
        self.columns = columns
        self.rows = rows
        self.results = results
        self.wall_time = wall_time

    @property
    def table(self) -> Any:
        """The table as a pandas DataFrame if pandas can be imported, else as the list of rows."""
        try:
            import pandas
        except ImportError:
            return self.rows
        return pandas.DataFrame(self.rows, columns=self.columns)

    def column(self, name: str) -> List[Any]:
        """The values of the table's column ``name``, one per variant (``KeyError`` naming the
        columns otherwise)."""
        if name not in self.columns:
            raise KeyError(f"no column '{name}' in the sweep's table (the columns are: {', '.join(self.columns)})")
        return [row[name] for row in self.rows]

    @property
    def failures(self) -> List[int]:
        """The indices of the variants that failed (their ``failure`` column says why)."""
        return [row["variant"] for row in self.rows if row["failure"] is not None]

    def __len__(self) -> int:
        return len(self.rows)

    def __repr__(self) -> str:
        return f"<flexmb.SweepResult: {len(self.rows)} variants, {len(self.failures)} failed>"


def variants(parameters: Mapping[str, Sequence[float]], integrators: Sequence[str], design: str = "grid") -> List[Tuple[Dict[str, float], str]]:
    """The variants of a sweep, in order: (parameters, integrator) pairs. ``design="grid"`` takes every
    combination of the parameters' values (the last parameter varying fastest), ``"zip"`` takes the
    k-th value of every parameter together (all lists of one length); the integrators vary fastest."""
    names = list(parameters)
    values = [list(parameters[name]) for name in names]
    if design == "grid":
        points = list(itertools.product(*values))
    elif design == "zip":
        lengths = {len(v) for v in values}
        if len(lengths) > 1:
            counts = ", ".join(f"{name}: {len(v)}" for name, v in zip(names, values))
            raise ValueError(f"design='zip' needs as many values for every parameter ({counts})")
        points = list(zip(*values))
    else:
        raise ValueError(f"design must be 'grid' or 'zip', got {design!r}")
    if not integrators:
        raise ValueError("integrators is empty: give at least one of 'bdf', 'adams', 'gen-alpha'")
    return [(dict(zip(names, map(float, point))), integrator) for point in points for integrator in integrators]


def _output_requests(outputs: Union[None, Sequence[str], Mapping[str, Any]]) -> List[Tuple[str, str, str]]:
    """(table column, result column, reduction) for each requested output."""
    if outputs is None:
        return []
    if isinstance(outputs, str):
        outputs = [outputs]
    if not isinstance(outputs, Mapping):
        return [(column, column, "final") for column in outputs]
    requests = []
    for name, asked in outputs.items():
        column, reduction = (asked, "final") if isinstance(asked, str) else tuple(asked)
        if reduction not in REDUCTIONS:
            raise ValueError(f"outputs[{name!r}]: unknown reduction {reduction!r} (known: {', '.join(REDUCTIONS)})")
        requests.append((name, column, reduction))
    return requests


def _reduce(time_values, values, reduction: str) -> float:
    """One number from a column (``values`` at ``time_values``) by ``reduction``."""
    if len(values) == 0:
        return math.nan
    if reduction == "final":
        return float(values[-1])
    if reduction == "initial":
        return float(values[0])
    if reduction == "min":
        return float(values.min())
    if reduction == "max":
        return float(values.max())
    if reduction == "max_abs":
        return float(abs(values).max())
    if reduction == "mean":
        return float(values.mean())
    if reduction == "time_of_min":
        return float(time_values[values.argmin()])
    if reduction == "time_of_max":
        return float(time_values[values.argmax()])
    # first_zero: the first row whose sign differs from the first row's, interpolated linearly.
    for k in range(1, len(values)):
        a, b = values[k - 1], values[k]
        if b == 0.0:
            return float(time_values[k])
        if (a < 0.0) != (b < 0.0):
            return float(time_values[k - 1] + (time_values[k] - time_values[k - 1]) * a / (a - b))
    return math.nan


def run_variant(model: str, parameters: Dict[str, float], integrator: str, settings: Dict[str, Any], outputs: List[Tuple[str, str, str]]) -> Tuple[Dict[str, Any], Any]:
    """Runs one variant where it is called (a worker): loads ``model`` with ``parameters``, simulates
    with ``integrator`` and ``settings`` (``simulate``'s keyword arguments) and reduces the outputs.
    Returns the variant's row (without its index) and its ``Results`` (``None`` when nothing ran); an
    error of the model, the run or an output fills the row's ``failure`` instead of being raised."""
    row: Dict[str, Any] = dict(parameters)
    row["integrator"] = integrator
    row.update({name: math.nan for name in COST_COLUMNS})
    row.update({name: math.nan for name, _, _ in outputs})
    row["failure"] = None
    results = None
    try:
        results = load(model, parameters=parameters).simulate(integrator=integrator, **settings)
    except SimulationError as error:
        results, row["failure"] = error.results, str(error)
    except Exception as error:  # a model that cannot be loaded or assembled, bad settings
        row["failure"] = f"{type(error).__name__}: {error}"
    if results is not None:
        stats = results.stats
        row.update(wall_time=stats["wall_time_s"], steps=stats["steps"], newton_iterations=stats["newton_iterations"], rejected_steps=stats["rejected_steps"])
    if results is not None and row["failure"] is None:
        try:
            for name, column, reduction in outputs:
                row[name] = _reduce(results.time, results[column], reduction)
        except KeyError as error:
            row["failure"] = f"outputs: {error.args[0]}"
    return row, results


def _workers() -> int:
    """The cores this process may use."""
    if hasattr(os, "sched_getaffinity"):
        return max(1, len(os.sched_getaffinity(0)))
    return os.cpu_count() or 1


def _failed_row(parameters: Dict[str, float], integrator: str, outputs, message: str) -> Dict[str, Any]:
    row: Dict[str, Any] = dict(parameters, integrator=integrator)
    row.update({name: math.nan for name in COST_COLUMNS})
    row.update({name: math.nan for name, _, _ in outputs})
    row["failure"] = message
    return row


def _on_futures(submit, jobs, outputs) -> List[Tuple[Dict[str, Any], Any]]:
    """Submits every job with ``submit(fn, *args)`` and gathers the answers in order; a worker that
    died fills the failure column of its variant."""
    futures = [submit(run_variant, *job) for job in jobs]
    done = []
    for future, (_, parameters, integrator, _, _) in zip(futures, jobs):
        try:
            done.append(future.result())
        except Exception as error:  # the worker process died, or the answer could not be sent back
            done.append((_failed_row(parameters, integrator, outputs, f"worker failed: {type(error).__name__}: {error}"), None))
    return done


def _on_ray(ray, jobs, outputs) -> List[Tuple[Dict[str, Any], Any]]:
    """Runs every job as a Ray task (one CPU each) on the cluster ``ray.init`` connected to (a local
    one if none) and gathers the answers in order."""
    remote = ray.remote(num_cpus=1)(run_variant)
    references = [remote.remote(*job) for job in jobs]
    done = []
    for reference, (_, parameters, integrator, _, _) in zip(references, jobs):
        try:
            done.append(ray.get(reference))
        except Exception as error:  # the task's worker died or the cluster went away
            done.append((_failed_row(parameters, integrator, outputs, f"Ray task failed: {type(error).__name__}: {error}"), None))
    return done


def _import_ray():
    try:
        import ray
    except ImportError as error:
        raise ImportError(f"executor='ray' needs Ray: pip install ray (then ray.init(address=...) to use a cluster) ({error})") from error
    return ray


def sweep(
    model: Union[str, "os.PathLike[str]"],
    parameters: Mapping[str, Sequence[float]],
    integrators: Sequence[str] = ("bdf",),
    outputs: Union[None, Sequence[str], Mapping[str, Any]] = None,
    t_end: Optional[float] = None,
    rtol: Optional[float] = None,
    atol: Optional[float] = None,
    output_step: Optional[float] = None,
    design: str = "grid",
    executor: Any = None,
    workers: Optional[int] = None,
) -> SweepResult:
    """Runs the model file ``model`` in every variant and gathers one table plus each run's results.

    The variants are the ``design`` of the ``parameters`` (name → list of values; ``"grid"``: every
    combination, ``"zip"``: the k-th values together) × ``integrators`` (``"bdf"``, ``"adams"``,
    ``"gen-alpha"``), the integrators varying fastest. ``t_end``, ``rtol``, ``atol`` and ``output_step``
    go to every ``simulate`` (``None``: the model file's).

    ``outputs`` are the table's result columns: a list of output column names (their final values), or
    a dict name → column (its final value) or name → (column, reduction), the reduction one of
    ``REDUCTIONS``: final, initial, min, max, max_abs, mean, time_of_min, time_of_max, first_zero.

    ``executor``: ``None`` or ``"processes"`` runs on local processes (a
    ``concurrent.futures.ProcessPoolExecutor`` with ``workers`` processes, default the cores this
    process may use); ``"ray"`` (or the ``ray`` module) runs Ray tasks on the cluster of the caller's
    ``ray.init(address=...)`` (a local Ray if none was started); ``"serial"`` runs here, one after the
    other; any object with ``submit(fn, *args)`` returning a future (a ``concurrent.futures.Executor``)
    is used as given. The model path is made absolute: on a cluster it must name the same file on
    every node.

    The table's columns: ``variant`` (the index), the parameters, ``integrator``, the cost
    (``wall_time``: the integration's wall time in s, ``steps``, ``newton_iterations``,
    ``rejected_steps``), the outputs, and ``failure`` (``None``, or why the variant failed; a failed
    variant does not stop the others, and its outputs are NaN)."""
    started = time.perf_counter()
    requests = _output_requests(outputs)
    clashes = sorted(set(parameters) & {"variant", "integrator", "failure", *COST_COLUMNS, *(name for name, _, _ in requests)})
    if clashes:
        raise ValueError(f"parameters and table columns share the names {', '.join(clashes)}: rename the outputs")
    path = os.path.abspath(os.fspath(model))
    settings = {key: value for key, value in dict(t_end=t_end, rtol=rtol, atol=atol, output_step=output_step).items() if value is not None}
    jobs = [(path, point, integrator, settings, requests) for point, integrator in variants(parameters, integrators, design)]
    if isinstance(executor, str) and executor not in ("serial", "processes", "ray"):
        raise ValueError(f"executor must be 'processes', 'ray', 'serial', the ray module or a concurrent.futures.Executor, got {executor!r}")
    if executor == "serial":
        done = [run_variant(*job) for job in jobs]
    elif executor is None or executor == "processes":
        count = min(workers or _workers(), max(1, len(jobs)))
        with concurrent.futures.ProcessPoolExecutor(max_workers=count) as pool:
            done = _on_futures(pool.submit, jobs, requests)
    elif executor == "ray" or getattr(executor, "__name__", None) == "ray":
        done = _on_ray(_import_ray() if executor == "ray" else executor, jobs, requests)
    elif hasattr(executor, "submit"):
        done = _on_futures(executor.submit, jobs, requests)
    else:
        raise ValueError(f"executor must be 'processes', 'ray', 'serial', the ray module or a concurrent.futures.Executor, got {executor!r}")
    columns = ["variant", *parameters, "integrator", *COST_COLUMNS, *(name for name, _, _ in requests), "failure"]
    rows = [{"variant": index, **row} for index, (row, _) in enumerate(done)]
    rows = [{name: row[name] for name in columns} for row in rows]
    return SweepResult(columns, rows, [results for _, results in done], time.perf_counter() - started)
