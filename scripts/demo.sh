#!/usr/bin/env bash
# The demo, no camera needed: a synthetic RGB-D camera swings around a
# textured scene, RISAS runs on every frame in a nodelet, and the overlay of
# matches to the previous frame appears on /risas/image. With a display it
# opens an image_view window (Ctrl-C to stop); without one it runs for
# DEMO_SECONDS (default 15), keeps the latest overlay in build/demo/overlay.png
# and prints the rate.
set -euo pipefail
"$(dirname "$0")/install_deps.sh"
source "$(dirname "$0")/env.sh"

mkdir -p "$RISAS_WS"
risas_build > "$RISAS_WS/build.log" 2>&1 || { tail -30 "$RISAS_WS/build.log"; exit 1; }
if [ -n "${DISPLAY:-}" ]; then
  exec roslaunch risas demo.launch view:=true
fi

out="$RISAS_ROOT/build/demo"
mkdir -p "$out"
rm -f "$out/overlay.png"
roslaunch risas demo.launch save:="$out/overlay.png" > "$out/roslaunch.log" 2>&1 &
launch=$!
trap 'kill -INT $launch 2>/dev/null; wait $launch 2>/dev/null || true' EXIT
sleep 5
echo "RISAS demo running headless; measuring /risas/keypoints for ${DEMO_SECONDS:-15} s ..."
timeout "${DEMO_SECONDS:-15}" rostopic hz /risas/keypoints 2>&1 | grep "average rate" | tail -1 || true
if [ -f "$out/overlay.png" ]; then
  echo "latest match overlay: $out/overlay.png"
else
  echo "no overlay was saved; see $out/roslaunch.log" >&2
  exit 1
fi
