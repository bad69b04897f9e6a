# Sourced by the shell tests that work in a scratch folder: sets `root` (the repository) and
# `work` (a new temporary folder, made the working directory and removed on exit), and fail().
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
fail() { echo "FAIL: $*" >&2; exit 1; }
