"""Every public name of the package has a docstring, and the type stubs (__init__.pyi) name the same
set: the package's, its classes' public methods and properties."""

import ast
import inspect

import flexmb
from conftest import REPOSITORY

STUBS = REPOSITORY / "python" / "flexmb" / "__init__.pyi"


def public(names):
    return {n for n in names if not n.startswith("_")}


def stub_tree():
    return ast.parse(STUBS.read_text())


def stub_names():
    """Top-level names the stubs define: functions, classes, annotated variables."""
    names = set()
    for node in stub_tree().body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.add(node.target.id)
    return names


def stub_members(cls):
    for node in stub_tree().body:
        if isinstance(node, ast.ClassDef) and node.name == cls:
            return {n.name for n in node.body if isinstance(n, ast.FunctionDef)} | {
                n.target.id for n in node.body if isinstance(n, ast.AnnAssign) and isinstance(n.target, ast.Name)
            }
    return set()


def test_every_public_name_has_a_docstring():
    missing = []
    for name in public(dir(flexmb)):
        value = getattr(flexmb, name)
        if inspect.ismodule(value) or not callable(value):
            continue
        if not (value.__doc__ or "").strip():
            missing.append(name)
        if inspect.isclass(value) and not issubclass(value, BaseException):
            for member in public(vars(value)):
                if not (getattr(value, member).__doc__ or "").strip():
                    missing.append(f"{name}.{member}")
    assert not missing, f"no docstring: {missing}"


def test_the_stubs_name_the_public_names():
    exported = public(dir(flexmb)) - {n for n in dir(flexmb) if inspect.ismodule(getattr(flexmb, n))}
    exported |= {"__version__"}
    assert stub_names() - {"_Path"} == exported
    assert set(flexmb.__all__) == exported


def test_the_stubs_name_each_classs_public_members():
    for name in public(dir(flexmb)):
        value = getattr(flexmb, name)
        if inspect.isclass(value) and not issubclass(value, BaseException):
            members = public(vars(value))
            assert stub_members(name) - {"__init__"} >= members, (name, members - stub_members(name))
