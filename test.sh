#!/usr/bin/env bash
# The whole test suite, what CI runs: the Rust workspace's tests, then the Python package built from
# this checkout (`pip install ./python`) and its tests (pytest). The package's wheel is built in the
# workspace's target directory, so that it reuses the engine crates the Rust tests compiled.
set -euo pipefail
cd "$(dirname "$0")"
cargo test --workspace --release
# The program the Python tests compare with (the CLI tests built it already; this only makes sure).
cargo build --release -p flexmb-cli
python3 -m pip --version >/dev/null
if ! python3 -c "import pytest, numpy" >/dev/null 2>&1; then
    python3 -m pip install --quiet pytest numpy
fi
# pandas for Results.to_pandas (optional: without it that test checks the ImportError only).
python3 -c "import pandas" >/dev/null 2>&1 || python3 -m pip install --quiet pandas || echo "note: could not install pandas"
# matplotlib for the plotting example of docs/python.md (binary wheels, about 2 min on the shared
# 2-core machine; without it that example's test is skipped, saying so).
python3 -c "import matplotlib" >/dev/null 2>&1 || python3 -m pip install --quiet matplotlib || echo "note: could not install matplotlib"
CARGO_TARGET_DIR="$PWD/target" python3 -m pip install --quiet ./python
FLEXMB_PROGRAM="$PWD/target/release/flexmb" python3 -m pytest python/tests
