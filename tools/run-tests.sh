#!/usr/bin/env bash
# Set up, build and pass the tests: the README's second command, and what CI runs.
# Extra arguments go to `meson test` (e.g. --suite unit).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
[ -d build ] || meson setup build
ninja -C build
tools/check-format.sh
rc=0
# The export test's tools are set up above: their absence is a failure here, not a skip.
export ACQ_REQUIRE_EXPORT_TOOLS=1
meson test -C build --print-errorlogs --num-processes 2 "$@" | tee build/meson-test.out || rc=$?
# One plain closing line that any reader of test output understands.
ok=$(awk '/^Ok:/ {print $2}' build/meson-test.out)
fail=$(awk '/^(Fail|Timeout|Unexpected Pass):/ {s += $NF} END {print s + 0}' build/meson-test.out)
echo "${ok:-0} passed, ${fail:-0} failed"
exit "$rc"
