#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ (clang, ASan + UBSan) into build/fuzz and runs each for
# a fixed time on a seed corpus made from the shipped files; exits non-zero if one crashed.
set -euo pipefail
all_targets=(fuzz_config fuzz_metadata fuzz_csv)
usage() {
  cat <<USAGE
Usage: bash scripts/fuzz.sh [--seconds N] [--target NAME]
Builds fuzz/ with clang into build/fuzz, then runs each fuzz target for N seconds (default 300)
and prints one line per target: inputs tried, crashes, seconds. Exits 1 if a target crashed
(an exception other than ConfigError escaped a reader, a sanitizer report, a hang or running
out of memory), naming the input that did it under out/fuzz/TARGET/.
  --seconds N    how long each target runs (a whole number > 0)
  --target NAME  only this target: ${all_targets[*]} (or config, metadata, csv)
The seed corpus is a scratch copy of the shipped configs, metadata and CSVs (the new inputs
libFuzzer finds go there too and are removed at the end). FLAGELLA_FUZZ_BUILD_DIR overrides
the build folder. A crash is reproduced by running the target on the artifact:
  build/fuzz/fuzz_config out/fuzz/fuzz_config/crash-...
USAGE
}
bad() {
  echo "fuzz: $* (--help)" >&2
  exit 2
}
seconds=300
targets=("${all_targets[@]}")
while [[ $# -gt 0 ]]; do
  case "$1" in
    -h | --help) usage; exit 0 ;;
    --seconds | --target)
      [[ $# -ge 2 ]] || bad "option $1 needs a value"
      if [[ "$1" == --seconds ]]; then seconds="$2"; else targets=("$2"); fi
      shift 2
      ;;
    --seconds=*) seconds="${1#*=}"; shift ;;
    --target=*) targets=("${1#*=}"); shift ;;
    *) bad "unexpected argument '$1'" ;;
  esac
done
[[ "$seconds" =~ ^[1-9][0-9]{0,6}$ ]] || bad "--seconds needs a whole number > 0, got '$seconds'"
[[ "${targets[0]}" == fuzz_* ]] || targets=("fuzz_${targets[0]}")
[[ " ${all_targets[*]} " == *" ${targets[0]} "* ]] ||
  bad "unknown target '${targets[0]#fuzz_}' (targets: ${all_targets[*]})"

source "$(dirname "${BASH_SOURCE[0]}")/env.sh"
cd "$FLAGELLA_ROOT"
build_dir="${FLAGELLA_FUZZ_BUILD_DIR:-$FLAGELLA_ROOT/build/fuzz}"
mkdir -p "$build_dir"
started=$SECONDS
{ CC=clang CXX=clang++ cmake -S fuzz -B "$build_dir" &&
  cmake --build "$build_dir" -j"$(nproc)" --target "${targets[@]}"; } > "$build_dir/build.log" 2>&1 ||
  { tail -40 "$build_dir/build.log"; echo "fuzz: build failed (log: $build_dir/build.log)" >&2; exit 1; }
echo "fuzz: built ${targets[*]} in $((SECONDS - started)) s ($build_dir)"

scratch="$(mktemp -d)"
trap 'rm -rf "$scratch"' EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
seed() {  # corpus folder, name tag, prefix text, files...: copies each file, prefixed
  local corpus="$1" tag="$2" prefix="$3" file
  shift 3
  for file in "$@"; do
    { printf '%s' "$prefix"; cat "$file"; } > "$corpus/$tag${file//\//_}"
  done
}
# 5 kB of text, placed where the readers never quote it: mutations can move it to where they do
# (an error message must not echo a long input whole).
long="$(head -c 5000 /dev/zero | tr '\0' w)"
make_corpus() {  # target: fills $scratch/TARGET with its seeds
  local corpus="$scratch/$1"
  mkdir -p "$corpus"
  case "$1" in
    fuzz_config)
      mapfile -t files < <(find config -name '*.yaml' | sort)
      seed "$corpus" "" "" "${files[@]}"
      # the same robots with a command-line override (fuzz_config.cpp: leading --set lines)
      seed "$corpus" set_ $'--set simulation.duration=1\n' config/*.yaml
      seed "$corpus" long_ $'--set robot.type='"$long"$'\n' config/helical_robot.yaml
      ;;
    fuzz_metadata)
      mapfile -t files < <(find config/identification -type f | sort)
      seed "$corpus" "" "" "${files[@]}" test/data/*.yaml fuzz/seeds/*.yaml
      sed "s/^description: .*/description: $long/" fuzz/seeds/time_series.yaml > "$corpus/long"
      ;;
    fuzz_csv)  # the first byte picks the reader (fuzz_csv.cpp): every CSV as table and series
      mapfile -t files < <(find config/identification test/data data/examples fuzz/seeds \
        -name '*.csv' | sort)
      seed "$corpus" table_ 0 "${files[@]}"
      seed "$corpus" series_ 1 "${files[@]}"
      printf '0# %s\nid, omega_T_rpm, v_mm_s\n%s, 3, 0.17\n' "$long" "$long" > "$corpus/long"
      ;;
  esac
}

failed=0
for target in "${targets[@]}"; do
  make_corpus "$target"
  artifacts="$FLAGELLA_ROOT/out/fuzz/$target"
  mkdir -p "$artifacts"
  log="$artifacts/last_run.log"
  started=$SECONDS
  status=0
  # TMPDIR: the files the targets write (fuzz_support.h) go with the scratch corpus, even after
  # a crash.
  TMPDIR="$scratch" UBSAN_OPTIONS="print_stacktrace=1${UBSAN_OPTIONS:+:$UBSAN_OPTIONS}" \
    "$build_dir/$target" -max_total_time="$seconds" -print_final_stats=1 -rss_limit_mb=2048 \
    -timeout=10 -max_len=16384 -len_control=0 -artifact_prefix="$artifacts/" "$scratch/$target" \
    > "$log" 2>&1 || status=$?
  # -print_final_stats=1: "stat::number_of_executed_units" (clang 14; "..._runs" elsewhere)
  runs="$(sed -En 's/^stat::number_of_executed_(units|runs): *//p' "$log" | tail -1)"
  mapfile -t written < <(sed -n 's/.*Test unit written to //p' "$log")
  crashes=${#written[@]}
  [[ $status -eq 0 || $crashes -gt 0 ]] || crashes=1  # died before writing its input
  printf 'fuzz: %-13s %10s inputs tried  %d crashes  %4d s\n' "$target" "${runs:-?}" "$crashes" \
    "$((SECONDS - started))"
  if [[ $status -ne 0 || $crashes -gt 0 ]]; then
    failed=1
    grep -m3 -E 'fuzz: DEFECT|ERROR: (Address|Leak|libFuzzer)|runtime error|deadly signal' "$log" |
      sed 's/^/    /' || true
    for a in "${written[@]}"; do echo "    input: $a (run: $build_dir/$target $a)"; done
    echo "    log: $log"
  fi
done
exit "$failed"
