#!/bin/bash
# The interface-flutter refinement study of docs/interface-flutter.md: `squeal cea` of
# pad-on-rotor.toml at contact-mesh levels f (default 1 2 4 8) and each setting (default all).
# Usage: bash examples/interface-flutter/run.sh OUT [LEVELS...]   (squeal, release build, on PATH;
# gmsh on PATH as for every meshed scene). Tables: python3 examples/interface-flutter/table.py OUT
set -eu
here=$(cd "$(dirname "$0")" && pwd)
out=${1:?output folder}; shift
levels=${*:-1 2 4 8}
mkdir -p "$out"
for f in $levels; do
  lv=(--set "components.0.geometry.n_circ=$((16 * f))" --set "components.0.geometry.n_rad=$((3 * f))"
      --set "components.1.geometry.n_elements=$f" --set "components.1.geometry.first_ring=$f"
      --set "components.1.geometry.last_ring=$((2 * f))")
  for setting in ${SETTINGS:-rigid mu035 ge01 kn1e9 kn1e8 kn1e7 kn1e6 kn1e5}; do
    case $setting in
      rigid) x=() ;;
      mu035) x=(--set 'friction.law={kind="constant",mu=0.35}') ;;
      ge01) x=(--set damping.w4=31416.0 --set 'damping.ge={pad=0.1}') ;;
      kn*) x=(--set "contact.0.normal_stiffness=${setting#kn}") ;;
      *) echo "unknown setting $setting" >&2; exit 2 ;;
    esac
    t0=$(date +%s)
    squeal -q cea "$here/pad-on-rotor.toml" --out "$out/L$f-$setting" --cache "$out/cache" \
      "${lv[@]}" "${x[@]}"
    echo "L$f $setting $(($(date +%s) - t0)) s" | tee -a "$out/times.log"
  done
done
