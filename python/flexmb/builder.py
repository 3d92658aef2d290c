"""A model built in code with the model file's vocabulary.

``ModelBuilder`` collects the tables of a model file — ``[model]``, ``[simulation]``, ``[parameters]``,
``[[body]]``, ``[[flexible_body]]``, ``[[marker]]``, ``[[joint]]``, ``[[driver]]``, ``[[measure]]``,
``[[force]]``, ``[[output]]`` — one call per table, its keywords the table's keys (docs/model-file.md),
and hands the text of that file to the loader of model files (``flexmb.loads``): validation, defaults
and error messages are the file's. ``to_toml()`` is the text, so a script can save its model as a file.
"""

import json
import math
import os
import re
import sys

from . import _native

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")
_TABLE_PATH = re.compile(r"^([a-z_]+)\[(\d+)\]")

# The arrays of tables of a model file, in the order the generated text writes them.
_ARRAYS = ("body", "flexible_body", "marker", "joint", "driver", "measure", "force", "output")


def _key(name):
    return name if _BARE_KEY.match(name) else json.dumps(name, ensure_ascii=False)


def _value(value, where):
    """A Python value as a TOML value: numbers, strings (expressions), booleans, lists, dicts (inline
    tables), paths; numpy arrays and scalars through ``tolist()``."""
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        value = value.tolist()
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)  # the shortest text that reads back as the same float
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, os.PathLike):
        return json.dumps(os.fspath(value), ensure_ascii=False)
    if isinstance(value, dict):
        items = ", ".join(f"{_key(str(k))} = {_value(v, f'{where}.{k}')}" for k, v in value.items())
        return "{ " + items + " }" if items else "{}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value(v, f"{where}[{i}]") for i, v in enumerate(value)) + "]"
    raise TypeError(f"{where}: cannot write a {type(value).__name__} in a model file: {value!r}")


def _caller():
    """``file:line`` of the script's call into the builder."""
    frame = sys._getframe(3)
    return f"{frame.f_code.co_filename}:{frame.f_lineno}"


class ModelBuilder:
    """A model built in code: one call per table of a model file, the keywords its keys.

        m = flexmb.ModelBuilder("pendulum", gravity=[0, -9.81, 0])
        m.parameter("L", 1.0)
        m.body("bob", mass=1.0, inertia=[1e-4, 1e-4, 1e-4], center_of_mass=[0, "-L", 0])
        m.marker("pivot_ground", body="ground", origin=[0, 0, 0])
        m.marker("pivot_bob", body="bob", origin=[0, 0, 0])
        m.joint("pivot", type="revolute", i="pivot_ground", j="pivot_bob")
        m.output(type="energy")
        model = m.build()

    Values are numbers, strings (expressions of the parameters, names), booleans, lists and dicts (inline
    tables such as ``orientation={"axis": [0, 0, 1], "angle_deg": 60}``). ``build()`` loads the text of
    ``to_toml()`` as the model file ``<ModelBuilder NAME>``: an error raises ``flexmb.ModelError`` with
    the file's message (key path, and the line of the generated text) followed by the builder call that
    made that table and where the script made it.
    """

    def __init__(self, name, gravity=None, base_dir=None):
        """A builder of the model ``name`` (``[model] name``), with ``gravity`` (m/s², ``[model]
        gravity``) if given; relative ``fe_model`` and ``body_file`` paths start at ``base_dir``
        (default: the current directory when ``build`` is called)."""
        self.name = name
        self.base_dir = base_dir
        self._model = {"name": name}
        if gravity is not None:
            self._model["gravity"] = gravity
        self._simulation = {}
        self._parameters = {}
        self._tables = {array: [] for array in _ARRAYS}
        self._calls = {array: [] for array in _ARRAYS}

    def _add(self, array, keys, call):
        self._tables[array].append(keys)
        self._calls[array].append(f"{call} at {_caller()}")
        return self

    def parameter(self, name, value):
        """``[parameters] name = value``: a number, or an expression of the parameters before it."""
        self._parameters[name] = value
        return self

    def simulation(self, **keys):
        """``[simulation]``: ``t_end``, ``output_step``, ``rtol``, ``atol``, ``integrator``, … (updates
        the keys given)."""
        self._simulation.update(keys)
        return self

    def body(self, name, **keys):
        """``[[body]]``: a rigid body; ``mass``, ``inertia``, ``center_of_mass``, ``position``,
        ``orientation``, ``velocity``, ``angular_velocity``, ``shape``, …"""
        return self._add("body", {"name": name, **keys}, f"body({name!r})")

    def flexible_body(self, name, **keys):
        """``[[flexible_body]]``: a flexible body reduced from an FE model file (``fe_model=PATH``,
        ``modes="4N5S"``) or read from a flexible-body file (``body_file=PATH``, as ``flexmb.modes``
        writes); ``damping``, ``position``, ``orientation``, …"""
        return self._add("flexible_body", {"name": name, **keys}, f"flexible_body({name!r})")

    def marker(self, name, **keys):
        """``[[marker]]``: a frame fixed on a body (``body``, ``origin`` or ``node``, ``orientation``)."""
        return self._add("marker", {"name": name, **keys}, f"marker({name!r})")

    def joint(self, name, **keys):
        """``[[joint]]``: ``type`` (``"revolute"``, ``"spherical"``, …) between markers ``i`` and ``j``."""
        return self._add("joint", {"name": name, **keys}, f"joint({name!r})")

    def driver(self, name, **keys):
        """``[[driver]]``: a prescribed motion (``type``, ``joint`` or markers, ``expression``, …)."""
        return self._add("driver", {"name": name, **keys}, f"driver({name!r})")

    def measure(self, name, **keys):
        """``[[measure]]``: a named quantity (``type``, ``joint`` or markers, …) that forces, drivers and
        outputs use."""
        return self._add("measure", {"name": name, **keys}, f"measure({name!r})")

    def force(self, name, **keys):
        """``[[force]]``: a force element (``type``: spring-damper, bushing, applied force, …)."""
        return self._add("force", {"name": name, **keys}, f"force({name!r})")

    def output(self, type=None, **keys):
        """``[[output]]``: what a run reports (``type``: ``"marker_position"``, ``"measure"``,
        ``"energy"``, …, with its keys)."""
        if type is not None:
            keys = {"type": type, **keys}
        return self._add("output", keys, f"output({keys.get('type')!r})")

    def to_toml(self):
        """The model file this builder describes, as text: saved to a file, ``flexmb.load`` gives the
        same model."""
        lines = [f"# Model file generated by flexmb.ModelBuilder({self.name!r}).", "", "[model]"]
        lines += [f"{_key(k)} = {_value(v, f'model.{k}')}" for k, v in self._model.items()]
        if self._simulation:
            lines += ["", "[simulation]"]
            lines += [f"{_key(k)} = {_value(v, f'simulation.{k}')}" for k, v in self._simulation.items()]
        if self._parameters:
            lines += ["", "[parameters]"]
            lines += [f"{_key(k)} = {_value(v, f'parameters.{k}')}" for k, v in self._parameters.items()]
        for array in _ARRAYS:
            for index, keys in enumerate(self._tables[array]):
                lines += ["", f"[[{array}]]"]
                lines += [f"{_key(k)} = {_value(v, f'{array}[{index}].{k}')}" for k, v in keys.items()]
        return "\n".join(lines) + "\n"

    def build(self, parameters=None, modes=None):
        """The ``flexmb.Model`` of this builder, loaded as ``flexmb.load`` loads a file (``parameters``
        and ``modes`` replace values as there). Raises ``flexmb.ModelError`` with the model file's
        message and the builder call of the table it names."""
        source = f"<ModelBuilder {self.name}>"
        base_dir = os.getcwd() if self.base_dir is None else os.fspath(self.base_dir)
        try:
            return _native.loads(self.to_toml(), source, base_dir, parameters, modes)
        except _native.ModelError as error:
            made_by = self._call_of(str(error), source)
            if made_by is None:
                raise
            raise _native.ModelError(f"{error} (made by {made_by})") from None

    def _call_of(self, message, source):
        """The builder call that made the table a model-file message names (``body[0].mass`` → the
        first ``body(...)``), if it names one."""
        if not message.startswith(source):
            return None
        located = message[len(source):].lstrip(":0123456789").lstrip()
        match = _TABLE_PATH.match(located)
        if match is None or match.group(1) not in self._calls:
            return None
        calls = self._calls[match.group(1)]
        index = int(match.group(2))
        return calls[index] if index < len(calls) else None

    def __repr__(self):
        counts = ", ".join(f"{len(t)} {a}" for a, t in self._tables.items() if t)
        return f"<flexmb.ModelBuilder {self.name!r}: {counts or 'empty'}>"
