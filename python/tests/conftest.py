"""Shared fixtures: the repository root, the squeal command (the CLI these tests agree with),
and CLI runs cached per session."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


def _squeal_bin() -> Path:
    env = os.environ.get("SQUEAL_BIN")
    if env:
        return Path(env)
    for profile in ("debug", "release"):
        p = ROOT / "target" / profile / "squeal"
        if p.exists():
            return p
    subprocess.run(["cargo", "build", "-q", "-p", "squeal-cli"], cwd=ROOT, check=True)
    return ROOT / "target" / "debug" / "squeal"


@pytest.fixture(scope="session")
def squeal_bin() -> Path:
    return _squeal_bin()


@pytest.fixture(scope="session")
def cli(squeal_bin, tmp_path_factory):
    """Runs `squeal ARGS --out DIR` once per distinct argument list; returns (dir, completed)."""
    runs = {}

    def run(*args: str, check: bool = True, out: bool = True):
        key = args
        if key not in runs:
            d = tmp_path_factory.mktemp("cli")
            cmd = [str(squeal_bin), "-q", *args] + (["--out", str(d)] if out else [])
            p = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True)
            if check and p.returncode != 0:
                raise AssertionError(f"{cmd} failed ({p.returncode}): {p.stderr}")
            runs[key] = (d, p)
        return runs[key]

    return run


def read_json(path: Path):
    return json.loads(Path(path).read_text())
