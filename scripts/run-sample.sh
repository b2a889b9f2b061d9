#!/usr/bin/env bash
# The README's main job: installs what squeal needs, builds it, and runs the built-in sample.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
bash scripts/setup.sh
cargo build --release --quiet -p squeal-cli --bin squeal
./target/release/squeal modes examples/sample-rotor.toml --out out/sample-rotor "$@"
echo "results: out/sample-rotor (modes.json, modes.vtu, summary.json)"
# The paper's sample-brake study (section 3, eight cases) on the coarse open brake
# (examples/sample-brake/study.toml): about 2 min on 2 cores (release build).
./target/release/squeal reproduce examples/sample-brake/study.toml --out out/reproduce
echo "study: out/reproduce (report.md, cases.json, cases.md, figures)"
