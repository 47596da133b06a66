# Sourced by the scripts: the environment ROS 1 on Debian 12 needs here.
# A pyenv python would shadow Debian's, which has catkin_pkg and rospkg.
export PYENV_VERSION=system
export ROS_HOSTNAME="${ROS_HOSTNAME:-localhost}"
export ROS_HOME="${ROS_HOME:-${TMPDIR:-/tmp}/risas_ros_home}"
mkdir -p "$ROS_HOME/log"
RISAS_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# The catkin workspace lives outside the repository: its src/risas links back
# to the repository, and a workspace inside it would make a link loop.
RISAS_WS="${RISAS_WS:-${XDG_CACHE_HOME:-$HOME/.cache}/risas_ws}"
RISAS_CMAKE_ARGS=(-DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release)

# Builds the package in the catkin workspace (the repository itself is the
# package) and sources its devel space.
risas_build() {
  mkdir -p "$RISAS_WS/src"
  local force=()
  # Another clone built here last: its configure may be newer than this
  # clone's files, so make alone would not notice the change of source.
  if [ "$(readlink "$RISAS_WS/src/risas" 2>/dev/null)" != "$RISAS_ROOT" ]; then
    ln -sfn "$RISAS_ROOT" "$RISAS_WS/src/risas"
    force=(--force-cmake)
  fi
  catkin_make -C "$RISAS_WS" "${RISAS_CMAKE_ARGS[@]}" "${force[@]}" -j"$(nproc)" "$@"
  # shellcheck disable=SC1091
  set +u; source "$RISAS_WS/devel/setup.bash"; set -u
  RISAS_BIN="$RISAS_WS/devel/lib/risas"
}
