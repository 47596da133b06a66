#!/usr/bin/env bash
# The demo, no camera needed: renders a short synthetic RGB-D sequence, then
# matches its first and last frame with RISAS and writes the overlay image.
set -euo pipefail
"$(dirname "$0")/install_deps.sh"
source "$(dirname "$0")/env.sh"

mkdir -p "$RISAS_WS"
risas_build > "$RISAS_WS/build.log" 2>&1 || { tail -30 "$RISAS_WS/build.log"; exit 1; }
out="$RISAS_ROOT/build/demo"
"$RISAS_BIN/risas_render_synthetic" --out "$out" --frames 3 --step-deg 6
"$RISAS_BIN/risas_match" --intrinsics "$out/camera-intrinsics.txt" \
  --rgb1 "$out/rgb_1.png" --depth1 "$out/depth_1.png" --rgb2 "$out/rgb_3.png" --depth2 "$out/depth_3.png" \
  --gt-rotation "$out/R1-3.txt" --gt-translation "$out/T1-3.txt" --overlay "$out/overlay.png"
