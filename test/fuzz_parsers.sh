#!/usr/bin/env bash
# The fuzz targets of the config and measured-data readers (fuzz/, scripts/fuzz.sh), 10 s each:
# fails if an input makes a reader throw anything but ConfigError, trips a sanitizer, hangs or
# gets an over-long message (the input is kept under out/fuzz/TARGET/). Bad arguments to the
# script are refused (exit 2) before it builds anything.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
for args in "--seconds 0" "--seconds" "--target nope" "stray"; do
  status=0
  # shellcheck disable=SC2086  # the words of $args are the arguments
  FLAGELLA_FUZZ_BUILD_DIR=/nonexistent/never-built bash "$root/scripts/fuzz.sh" $args \
    > /dev/null 2>&1 || status=$?
  [[ $status -eq 2 ]] || { echo "FAIL: 'fuzz.sh $args' exited $status, expected 2" >&2; exit 1; }
done
bash "$root/scripts/fuzz.sh" --seconds 10
