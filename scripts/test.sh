#!/usr/bin/env bash
# Sets up a virtualenv (.venv, or $UAVCOV_VENV), builds and installs uavcov with its test extras,
# then runs every test: the Rust core's (cargo test) and the Python suite (pytest).
# Extra arguments go to pytest, e.g. `bash scripts/test.sh -k visibility`.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${UAVCOV_VENV:-.venv}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q --upgrade pip
"$venv/bin/python" -m pip install -q ".[test]"
echo "== cargo test (pure Rust core, no Python)"
cargo test --release --quiet
echo "== pytest"
"$venv/bin/python" -m pytest -q -p no:cacheprovider "$@"
