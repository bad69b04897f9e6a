# Sourced by the other scripts: the system python must come first (a pyenv python3 on PATH
# lacks catkin_pkg; see docs/ros-notes in the README), and the workspace root is exported.
export PATH="/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
FLAGELLA_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export FLAGELLA_ROOT
