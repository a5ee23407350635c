#!/usr/bin/env bash
# Builds the Python package into a virtual environment under target/ (a debug build that
# shares the workspace's compiled crates) and runs its pytest suite.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=target/py-venv
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q --disable-pip-version-check 'maturin>=1.5,<2' pytest numpy scikit-image
# maturin develop builds the extension in the dev profile into the environment.
VIRTUAL_ENV="$PWD/$venv" "$venv/bin/maturin" develop -q
"$venv/bin/python" -m pytest -q python/tests "$@"
