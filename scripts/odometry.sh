#!/usr/bin/env bash
# Reproduces docs/odometry.md: risas::Odometry on RISAS and on ORB features
# over the three TUM-layout recordings, ATE and RPE, and the plots; then
# the tables of "Where the keyframes fall" for fr1_xyz and the kitchen (a
# chain of keyframes from each of several starting frames, at 30, 15 and
# 10 Hz), and the covariance checks over the same chains. Usage:
#   scripts/odometry.sh [TUM_ROOT] [OUT_DIR]
# (defaults: ../shared/data/tum next to the repository, build/odometry).
# About eight minutes on 2 cores, seven of them the chains.
set -euo pipefail
"$(dirname "$0")/install_deps.sh"
source "$(dirname "$0")/env.sh"

tum="${1:-$RISAS_ROOT/../shared/data/tum}"
out="${2:-$RISAS_ROOT/build/odometry}"
[ -d "$tum" ] || { echo "no TUM recordings at $tum" >&2; exit 1; }
mkdir -p "$RISAS_WS" "$out"
risas_build > "$RISAS_WS/build.log" 2>&1 || { tail -30 "$RISAS_WS/build.log"; exit 1; }

# The runs: RISAS at the defaults, RISAS with config/odometry.yaml
# (RISAS_vo), ORB, and ORB's strongest keypoint within 3 px only
# (ORB-distinct); 8 RANSAC seeds each.
runs=(RISAS RISAS_vo ORB ORB-distinct)
# name folder fx fy cx cy, as ../shared/data/tum/README.md gives them, and
# the chains' starting frames at 30 Hz ("-": no chains; the cabinet's are
# keyframes, not a camera's frames at its rate).
recordings=(
  "fr1_xyz fr1_xyz 517.3 516.5 318.6 255.3 0,4,8,12,16"
  "fr3_cabinet fr3_cabinet_keyframes 535.4 539.2 320.1 247.6 -"
  "7scenes_redkitchen 7scenes_redkitchen 585 585 320 240 0,7,14,21,28"
)
# track RUN FOLDER FX FY CX CY [risas_odometry options...]
track() {
  local run="$1" folder="$2" fx="$3" fy="$4" cx="$5" cy="$6"
  shift 6
  local params=()
  [ "$run" = RISAS_vo ] && params=(--params "$RISAS_ROOT/config/odometry.yaml")
  "$RISAS_BIN/risas_odometry" --tum "$folder" --fx "$fx" --fy "$fy" --cx "$cx" --cy "$cy" \
    --features "${run%_vo}" "${params[@]}" --ransac-seeds 8 "$@"
}

for recording in "${recordings[@]}"; do
  read -r name folder fx fy cx cy _ <<< "$recording"
  for run in "${runs[@]}"; do
    echo "== $name, $run"
    track "$run" "$tum/$folder" "$fx" "$fy" "$cx" "$cy" --out "$out/${name}_${run}.txt" --frames "$out/${name}_${run}.csv"
  done
  "$RISAS_ROOT/scripts/plot_trajectory.py" "$tum/$folder/groundtruth.txt" \
    "$out/${name}_RISAS.txt=RISAS" "$out/${name}_RISAS_vo.txt=RISAS (odometry.yaml)" "$out/${name}_ORB.txt=ORB" \
    "$out/${name}_ORB-distinct.txt=ORB-distinct" \
    --out "$out/${name}.png"
done

# The chains of "Where the keyframes fall": at 30 Hz one from each of five
# starting frames; every second frame from 0 and 1; every third from 0, 1
# and 2. A cell of NAME_chains.md is the mean over the chains of each
# chain's mean ATE, and the chains' range; NAME_chains_covariance.md has
# the covariance checks of "The pose covariance" and "The twist" over the
# same chains (each chain's first seed): the mean and range of the
# position's and the rotation's mean |e|^2 / mean sigma^2.
header="| features | 30 Hz, 5 starts | 15 Hz, 2 | 10 Hz, 3 |"
# A check's line over the chains as a cell: "position 0.93 (0.60–1.21),
# rotation 4.26 (3.44–5.17)".
ratios='s/.*sigma\^2 mean ([0-9.]+), from ([0-9.]+) to ([0-9.]+); rotation mean ([0-9.]+), from ([0-9.]+) to ([0-9.]+)$/position \1 (\2–\3), rotation \4 (\5–\6)/p'
for recording in "${recordings[@]}"; do
  read -r name folder fx fy cx cy starts30 <<< "$recording"
  [ "$starts30" = - ] && continue
  table="$out/${name}_chains.md" covariances="$out/${name}_chains_covariance.md"
  printf '%s\n|---|---|---|---|\n' "$header" > "$table"
  drift_rows=() motion_rows=()
  for run in "${runs[@]}"; do
    row="| $run |" drift_row="| $run |" motion_row="| $run |"
    for chains in "1 $starts30" "2 0,1" "3 0,1,2"; do
      read -r step starts <<< "$chains"
      log="$out/${name}_chains_${run}_step${step}.log"
      echo "== $name, $run, step $step, from frames $starts"
      track "$run" "$tum/$folder" "$fx" "$fy" "$cx" "$cy" --step "$step" --start "$starts" \
        --out "$out/${name}_chains_${run}_step${step}.txt" | tee "$log"
      row+=" $(sed -nE 's/^ATE RMSE over .* chains .*: mean ([0-9.]+) m, from ([0-9.]+) to ([0-9.]+) m$/\1 m (\2–\3)/p' "$log") |"
      drift_row+=" $(sed -nE "/^Covariance against the drift over /$ratios" "$log") |"
      motion_row+=" $(sed -nE "/^Frame-to-frame motion's covariance \(the twist's\) over /$ratios" "$log") |"
    done
    echo "$row" >> "$table"
    drift_rows+=("$drift_row") motion_rows+=("$motion_row")
  done
  {
    echo "The pose's covariance against the drift from the first tracked pose:"
    echo
    printf '%s\n|---|---|---|---|\n' "$header"
    printf '%s\n' "${drift_rows[@]}"
    echo
    echo "The frame-to-frame motion's covariance (the twist's) against the truth's motion:"
    echo
    printf '%s\n|---|---|---|---|\n' "$header"
    printf '%s\n' "${motion_rows[@]}"
  } > "$covariances"
  cat "$table" "$covariances"
done
