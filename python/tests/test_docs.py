"""The Python examples of the README and of docs/python.md run as written, from the repository's root."""

import contextlib
import io
import re

import pytest

from conftest import REPOSITORY


def python_blocks(path, plotting=False):
    """The fenced Python examples of `path`: without those that plot with matplotlib (which the package
    does not need), or only those with `plotting`. Only blocks fenced ```python run; an example that
    cannot run here (one that needs a Ray cluster) is fenced ```py and shown only."""
    blocks = re.findall(r"```python\n(.*?)```", path.read_text(), flags=re.S)
    return [b for b in blocks if ("import matplotlib" in b) == plotting]


@pytest.mark.parametrize("page", ["README.md", "docs/python.md"])
def test_the_examples_run_as_written(page, monkeypatch):
    blocks = python_blocks(REPOSITORY / page)
    assert blocks, f"{page} has no Python example"
    monkeypatch.chdir(REPOSITORY)
    namespace = {"__name__": "__example__"}
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        for block in blocks:
            exec(compile(block, f"{page} example", "exec"), namespace)
    assert printed.getvalue(), f"the examples of {page} print what they show"


def test_the_examples_print_what_their_comments_show(monkeypatch):
    # In docs/python.md, a print whose comment starts with `→` shows what it prints (`…` standing for
    # any text, ` — ` starting a remark).
    monkeypatch.chdir(REPOSITORY)
    namespace = {"__name__": "__example__"}
    shown = 0
    for block in python_blocks(REPOSITORY / "docs" / "python.md"):
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            exec(compile(block, "docs/python.md example", "exec"), namespace)
        comments = [re.search(r"#\s*(.*)$", line).group(1) if "#" in line else "" for line in block.splitlines() if "print(" in line]
        lines = printed.getvalue().splitlines()
        assert len(lines) == len(comments), block
        for line, comment in zip(lines, comments):
            if comment.startswith("→ "):
                expected = comment[2:].split(" — ")[0].split("…")
                assert line.startswith(expected[0]) and line.endswith(expected[-1]), (line, comment)
                shown += 1
    assert shown >= 5


def test_the_plotting_example_runs_with_matplotlib(monkeypatch):
    # docs/python.md's matplotlib example, on its own: skipped, saying why, where matplotlib is absent
    # (./test.sh installs it).
    pytest.importorskip("matplotlib", reason="matplotlib is not installed: the plotting example of docs/python.md was not run")
    blocks = python_blocks(REPOSITORY / "docs" / "python.md", plotting=True)
    assert blocks, "docs/python.md has a plotting example"
    monkeypatch.chdir(REPOSITORY)
    for block in blocks:
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed):
            exec(compile(block, "docs/python.md plotting example", "exec"), {"__name__": "__example__"})
        assert printed.getvalue().strip() == "pendulum.png True", printed.getvalue()
