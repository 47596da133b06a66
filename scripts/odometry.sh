#!/usr/bin/env bash
# Reproduces docs/odometry.md: risas::Odometry on RISAS and on ORB features
# over the three TUM-layout recordings, ATE and RPE, and the plots. Usage:
#   scripts/odometry.sh [TUM_ROOT] [OUT_DIR]
# (defaults: ../shared/data/tum next to the repository, build/odometry).
# About a minute on 2 cores.
set -euo pipefail
"$(dirname "$0")/install_deps.sh"
source "$(dirname "$0")/env.sh"

tum="${1:-$RISAS_ROOT/../shared/data/tum}"
out="${2:-$RISAS_ROOT/build/odometry}"
[ -d "$tum" ] || { echo "no TUM recordings at $tum" >&2; exit 1; }
mkdir -p "$RISAS_WS" "$out"
risas_build > "$RISAS_WS/build.log" 2>&1 || { tail -30 "$RISAS_WS/build.log"; exit 1; }

# name folder intrinsics, as ../shared/data/tum/README.md gives them
while read -r name folder fx fy cx cy; do
  # RISAS at the defaults, RISAS with config/odometry.yaml (RISAS_vo), ORB,
  # and ORB's strongest keypoint within 3 px only (ORB-distinct).
  for run in RISAS RISAS_vo ORB ORB-distinct; do
    echo "== $name, $run"
    params=()
    [ "$run" = RISAS_vo ] && params=(--params "$RISAS_ROOT/config/odometry.yaml")
    "$RISAS_BIN/risas_odometry" --tum "$tum/$folder" --fx "$fx" --fy "$fy" --cx "$cx" --cy "$cy" \
      --features "${run%_vo}" "${params[@]}" --out "$out/${name}_${run}.txt" --frames "$out/${name}_${run}.csv" \
      --ransac-seeds 8
  done
  "$RISAS_ROOT/scripts/plot_trajectory.py" "$tum/$folder/groundtruth.txt" \
    "$out/${name}_RISAS.txt=RISAS" "$out/${name}_RISAS_vo.txt=RISAS (odometry.yaml)" "$out/${name}_ORB.txt=ORB" \
    "$out/${name}_ORB-distinct.txt=ORB-distinct" \
    --out "$out/${name}.png"
done <<'LIST'
fr1_xyz fr1_xyz 517.3 516.5 318.6 255.3
fr3_cabinet fr3_cabinet_keyframes 535.4 539.2 320.1 247.6
7scenes_redkitchen 7scenes_redkitchen 585 585 320 240
LIST
