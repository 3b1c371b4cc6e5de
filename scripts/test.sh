#!/usr/bin/env bash
# Sets up a virtualenv (.venv, or $UAVCOV_VENV), builds and installs uavcov with its test extras,
# then runs every check: the Rust core's formatting, lints and tests (no Python needed), the
# Python package's lints and types, the Python suite with the doctests, the documentation site,
# and that site opened in headless Chromium.
# Extra arguments go to pytest, e.g. `bash scripts/test.sh -k visibility`.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${UAVCOV_VENV:-.venv}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
echo "== installing uavcov with its [test,docs] extras into $venv: about 10 minutes the first time (the Rust extension compiles), a minute or two after"
"$venv/bin/python" -m pip install -q --upgrade pip
"$venv/bin/python" -m pip install -q ".[test,docs]"
# The binding's lints compile PyO3, which looks for this interpreter.
export PYO3_PYTHON="$PWD/$venv/bin/python"
[ "${venv#/}" != "$venv" ] && export PYO3_PYTHON="$venv/bin/python"
echo "== cargo fmt --check"
cargo fmt --check
echo "== cargo clippy (every target, every feature, warnings are errors)"
cargo clippy --quiet --all-targets --all-features -- -D warnings
echo "== cargo test (pure Rust core, no Python)"
cargo test --release --quiet
echo "== ruff (lint and format)"
"$venv/bin/ruff" check python tests benches scripts docs/figures docs/conf.py docs/_ext docs/_inventories docs/tutorials docs/gallery
"$venv/bin/ruff" format --check python tests benches scripts docs/figures docs/conf.py docs/_ext docs/_inventories docs/tutorials docs/gallery
echo "== mypy (the package)"
"$venv/bin/mypy"
echo "== pytest (the suite, with the README's quick start; the site's test runs after the site is built)"
"$venv/bin/python" -m pytest -q -p no:cacheprovider tests --ignore=tests/test_site.py "$@"
echo "== doctests (the installed package's docstrings)"
"$venv/bin/python" -m pytest -q -p no:cacheprovider --doctest-modules --pyargs uavcov
echo "== docs (the site, warnings are errors, every tutorial run)"
UAVCOV_VENV="$venv" bash scripts/docs.sh
echo "== the site in headless Chromium (getting started, the gallery)"
"$venv/bin/python" -m pytest -q -p no:cacheprovider tests/test_site.py
