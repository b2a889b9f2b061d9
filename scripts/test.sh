#!/usr/bin/env bash
# The README's test command: installs what the tests need, then runs every test of the workspace
# and the Python package's pytest suite (against the CLI's files: target/debug/squeal).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
bash scripts/setup.sh
status=0
# A clean CI build gains nothing from incremental compilation, and its files fill the disk.
if [[ "${CI:-}" == "true" ]]; then export CARGO_INCREMENTAL=0; fi
cargo test --workspace --no-fail-fast "$@" || status=$?
# The Python package: built in the workspace's dev profile into target/debug (the numerical
# crates at opt-level 2, shared with the cargo tests above), installed into .venv, tested.
start=$SECONDS
bash scripts/install-python.sh
.venv/bin/python -m pytest -q -p no:cacheprovider python/tests || status=$?
echo "test.sh: Python package build + tests: $((SECONDS - start)) s"
exit "$status"
