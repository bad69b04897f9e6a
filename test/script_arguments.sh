#!/usr/bin/env bash
# The two commands refuse bad arguments before they set up, build, run or remove anything:
# run_tests.sh with a stray word or an option missing its value exits 2 (it used to run the whole
# suite and exit 0); run_main.sh prints its arguments with --help and exits 2 on an argument that
# is not NAME:=VALUE, not an argument of the launch file, or set by the script itself, leaving
# the previous run's outputs in place. Runs on a copy of the scripts and the launch file.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/scratch_dir.sh"
mkdir -p "$work/scripts" "$work/launch" "$work/out/main"
cp "$root"/scripts/*.sh "$root"/scripts/*.py "$work/scripts/"
cp "$root/launch/path_following.launch" "$work/launch/"
# setup.sh and build.sh must never be reached: make them fail loudly if they are.
for s in setup.sh build.sh; do printf 'echo "%s reached" >&2; exit 99\n' "$s" >"$work/scripts/$s"; done
for f in path_following.bag path_following.png summary.json; do echo previous >"$work/out/main/$f"; done

expect_exit() {  # expected status, expected text in the output, command...
  local want="$1" text="$2"
  shift 2
  local out status=0
  out="$("$@" 2>&1)" || status=$?
  [[ "$status" == "$want" ]] || fail "'$*' exited $status, expected $want: $out"
  [[ "$out" == *"$text"* ]] || fail "'$*' did not print '$text': $out"
  echo "ok: '$*' -> $status"
}

expect_exit 2 "unexpected argument 'xyzzy'" bash "$work/scripts/run_tests.sh" xyzzy
expect_exit 2 "option -R needs a value" bash "$work/scripts/run_tests.sh" -R
expect_exit 0 "-R REGEX" bash "$work/scripts/run_tests.sh" --help
expect_exit 0 "mode:=" bash "$work/scripts/run_main.sh" --help
expect_exit 0 "camera_noise:=" bash "$work/scripts/run_main.sh" -h
expect_exit 2 "is not NAME:=VALUE" bash "$work/scripts/run_main.sh" xyzzy
expect_exit 2 "unknown argument 'foo'" bash "$work/scripts/run_main.sh" mode:=open_loop foo:=1
expect_exit 2 "'bag' is set by this script" bash "$work/scripts/run_main.sh" bag:=/tmp/x.bag
for f in path_following.bag path_following.png summary.json; do
  [[ "$(cat "$work/out/main/$f")" == previous ]] || fail "out/main/$f was touched"
done
echo "PASS: bad arguments refused before anything ran; previous outputs kept"
