#!/usr/bin/env bash
# The two commands refuse bad arguments before they set up, build, run or remove anything:
# run_tests.sh with a stray word or an option missing its value exits 2 (it used to run the whole
# suite and exit 0); run_main.sh prints its arguments with --help and exits 2 on an argument that
# is not NAME:=VALUE, not an argument of the launch file, or set by the script itself, leaving
# the previous run's outputs in place. Runs on a copy of the scripts and the launch file.
set -euo pipefail
SRC="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WORK="$(mktemp -d)"
trap 'rm -rf "$WORK"' EXIT
mkdir -p "$WORK/scripts" "$WORK/launch" "$WORK/out/main"
cp "$SRC"/scripts/*.sh "$SRC"/scripts/*.py "$WORK/scripts/"
cp "$SRC/launch/path_following.launch" "$WORK/launch/"
# setup.sh and build.sh must never be reached: make them fail loudly if they are.
for s in setup.sh build.sh; do printf 'echo "%s reached" >&2; exit 99\n' "$s" >"$WORK/scripts/$s"; done
for f in path_following.bag path_following.png summary.json; do echo previous >"$WORK/out/main/$f"; done
fail() { echo "FAIL: $*" >&2; exit 1; }

expect_exit() {  # expected status, expected text in the output, command...
  local want="$1" text="$2"
  shift 2
  local out status=0
  out="$("$@" 2>&1)" || status=$?
  [[ "$status" == "$want" ]] || fail "'$*' exited $status, expected $want: $out"
  [[ "$out" == *"$text"* ]] || fail "'$*' did not print '$text': $out"
  echo "ok: '$*' -> $status"
}

expect_exit 2 "unexpected argument 'xyzzy'" bash "$WORK/scripts/run_tests.sh" xyzzy
expect_exit 2 "option -R needs a value" bash "$WORK/scripts/run_tests.sh" -R
expect_exit 0 "-R REGEX" bash "$WORK/scripts/run_tests.sh" --help
expect_exit 0 "mode:=" bash "$WORK/scripts/run_main.sh" --help
expect_exit 0 "camera_noise:=" bash "$WORK/scripts/run_main.sh" -h
expect_exit 2 "is not NAME:=VALUE" bash "$WORK/scripts/run_main.sh" xyzzy
expect_exit 2 "unknown argument 'foo'" bash "$WORK/scripts/run_main.sh" mode:=open_loop foo:=1
expect_exit 2 "'bag' is set by this script" bash "$WORK/scripts/run_main.sh" bag:=/tmp/x.bag
for f in path_following.bag path_following.png summary.json; do
  [[ "$(cat "$WORK/out/main/$f")" == previous ]] || fail "out/main/$f was touched"
done
echo "PASS: bad arguments refused before anything ran; previous outputs kept"
