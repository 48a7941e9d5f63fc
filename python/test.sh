#!/usr/bin/env bash
# The Python module's tests: build the module into a virtual environment
# under target/ (sharing the crate's release build) and run pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
python3 -m venv target/python-venv
# shellcheck disable=SC1091
. target/python-venv/bin/activate
pip install --quiet --disable-pip-version-check maturin numpy pytest
CARGO_TARGET_DIR="$PWD/target" pip install --quiet --disable-pip-version-check ./python
python -m pytest -q python/tests
