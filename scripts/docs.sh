#!/usr/bin/env bash
# Builds the documentation site into docs/_build/html (open docs/_build/html/index.html).
# Warnings are errors (-W --keep-going, nitpicky): a broken cross-reference, a docstring that
# does not parse or a tutorial that raises fails the build. Runs every tutorial and gallery
# script. Uses the virtualenv $UAVCOV_VENV (default .venv) with the docs extra installed
# (`pip install -e '.[docs]'`, or scripts/test.sh, which installs it and calls this script).
# Extra arguments go to sphinx-build, e.g. `bash scripts/docs.sh -j 2`.
set -euo pipefail
cd "$(dirname "$0")/.."
venv="${UAVCOV_VENV:-.venv}"
rm -rf docs/_build docs/auto_tutorials docs/auto_gallery docs/api/generated
# Figures on pages are drawn off screen.
MPLBACKEND=Agg "$venv/bin/python" -m sphinx -b html -W --keep-going -n -q docs docs/_build/html "$@"
echo "docs: docs/_build/html/index.html"
