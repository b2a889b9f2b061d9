#!/usr/bin/env bash
# Installs the Python package `squeal` (python/: the squeal-py extension crate + the Python
# sources) from this checkout into the project's virtual environment, idempotently (re-running
# rebuilds only what changed). Offline once maturin is in the venv (scripts/setup.sh puts it
# there): no build isolation, no dependency download.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
bash scripts/setup.sh
# maturin's pyo3 configuration reads the interpreter first on PATH: the venv's.
PATH="$root/.venv/bin:$PATH" .venv/bin/python -m pip install --quiet --disable-pip-version-check \
  --no-build-isolation --no-deps --no-index ./python
