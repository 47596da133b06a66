#!/usr/bin/env bash
# build_catkin_consumer.sh INSTALL_SPACE WS CONSUMER_SOURCE: builds
# test/downstream/catkin_consumer in a workspace of its own on top of risas's
# catkin install space alone (not its devel space or source tree), as a
# user's second package sees it, runs it, and checks that the installed
# risas_evaluate finds its installed plot script.
set -euo pipefail
install_space=$(realpath "$1") ws=$2 consumer_source=$3
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$ws"
mkdir -p "$ws/src"
cp -r "$here/catkin_consumer" "$ws/src/risas_catkin_consumer"
# A clean environment: nothing of the test run's own workspace leaks in.
env -i HOME="$HOME" PATH=/usr/bin:/bin PYENV_VERSION=system ROS_HOME="${ROS_HOME:-/tmp}" bash --norc -c '
  set -eu
  set +u; source "$1/setup.bash"; set -u
  catkin_make -C "$2" -DPYTHON_EXECUTABLE=/usr/bin/python3 -DRISAS_CONSUMER_SOURCE="$3" > "$2/build.log" 2>&1 ||
    { tail -30 "$2/build.log"; exit 1; }
  "$2/devel/lib/risas_catkin_consumer/risas_consumer"
  expected="plots with $1/share/risas/scripts/plot_evaluation.py"
  "$1/lib/risas/risas_evaluate" --help | grep -qF "$expected" ||
    { echo "installed risas_evaluate does not say: $expected"; exit 1; }
  echo "installed risas_evaluate: $expected"
' _ "$install_space" "$ws" "$consumer_source"
