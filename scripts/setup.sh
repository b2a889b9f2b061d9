#!/usr/bin/env bash
# Installs what squeal needs beside the Rust toolchain, idempotently:
# a project-local Python virtual environment (.venv) with the gmsh program (the mesher) and the
# Python peers the tests cross-check against (meshio, numpy, scipy, pyNastran, scikit-fem), and what the
# Python package `squeal` is built and tested with (maturin, pytest, pandas, dask[distributed],
# tqdm). The package itself is installed by scripts/install-python.sh.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
venv="$root/.venv"
stamp="$venv/.squeal-setup-v4"
pkgs=(gmsh meshio numpy scipy pyNastran pyyeti "maturin>=1.9,<2" pytest pandas "dask[distributed]" tqdm scikit-fem)
if [[ -f "$stamp" ]]; then
  exit 0
fi
if [[ ! -x "$venv/bin/python" ]]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check "${pkgs[@]}"
# The pip gmsh library loads X11/GL shared libraries even headless; install them if missing.
if ! "$venv/bin/python" -c "import gmsh" >/dev/null 2>&1; then
  if command -v apt-get >/dev/null 2>&1; then
    echo "setup: installing the shared libraries gmsh needs (apt-get)" >&2
    apt-get update -qq && apt-get install -y -qq libglu1-mesa libgl1 libxrender1 libxcursor1 \
      libxfixes3 libxext6 libxft2 libfontconfig1 libxinerama1 libgomp1 >/dev/null
  fi
  "$venv/bin/python" -c "import gmsh" || { echo "setup: gmsh does not import" >&2; exit 1; }
fi
"$venv/bin/python" "$venv/bin/gmsh" --version >/dev/null 2>&1 || { echo "setup: gmsh program does not run" >&2; exit 1; }
touch "$stamp"
