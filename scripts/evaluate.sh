#!/usr/bin/env bash
# Reproduces docs/evaluation.md: every method on every sequence of the
# dataset, then the paper's two parameter studies. Usage:
#   scripts/evaluate.sh [DATASET_ROOT] [OUT_DIR]
# (defaults: ../shared/data/ManipulatorsDataset next to the repository, and
# build/evaluation). About 15 minutes on 2 cores.
set -euo pipefail
"$(dirname "$0")/install_deps.sh"
source "$(dirname "$0")/env.sh"

data="${1:-$RISAS_ROOT/../shared/data/ManipulatorsDataset}"
out="${2:-$RISAS_ROOT/build/evaluation}"
[ -d "$data" ] || { echo "no dataset at $data" >&2; exit 1; }
mkdir -p "$RISAS_WS" "$out"
risas_build > "$RISAS_WS/build.log" 2>&1 || { tail -30 "$RISAS_WS/build.log"; exit 1; }
evaluate="$RISAS_BIN/risas_evaluate"

echo "== all methods, all sequences -> $out/methods"
"$evaluate" --data "$data" --out "$out/methods"
echo "== study: n_pie x n_bin x n_vec -> $out/study_bins"
"$evaluate" --data "$data" --study bins --out "$out/study_bins" | tail -20
echo "== study: tau -> $out/study_tau"
"$evaluate" --data "$data" --study tau --out "$out/study_tau" | tail -12
