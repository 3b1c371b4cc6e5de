#!/usr/bin/env bash
# Sets up a virtualenv (.venv, or $UAVCOV_VENV), builds and installs uavcov, then runs the main
# job: `uavcov demo`. Extra arguments go to the demo, e.g. `bash scripts/demo.sh --out out/demo`.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${UAVCOV_VENV:-.venv}"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
# pip is quiet: say what the silent minutes are (the extension's first compile is the long part).
echo "== installing uavcov and its [plot] extra into $venv: about 10 minutes the first time (the Rust extension compiles), a minute or two after" >&2
"$venv/bin/python" -m pip install -q --upgrade pip
"$venv/bin/python" -m pip install -q ".[plot]"
"$venv/bin/python" -m uavcov demo "$@"
