#!/usr/bin/env bash
# acqd on bad plans (tests/plans/*.yaml, each one problem away from good.yaml): each must exit 1
# before any device is opened or moved, naming the plan's file:line:column (or the directions
# file's line) and the problem. good.yaml passes --dry-run and prints an order and a time.
# usage: test_plans.sh ACQD PLANS_DIR DATA_DIR
set -u
acqd=$1
plans=$2
data=$3
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp "$plans"/*.yaml "$tmp/"
cp "$data/directions/seed_directions_20.tsv" "$tmp/directions.tsv"
cp "$data/nbrdf/merl/white-paint.h5" "$data/nbrdf/merl/brass.h5" "$tmp/"
: > "$tmp/basis.acqb"  # the loader checks that the basis exists; the capture reads it
failures=0
passed=0

expect() {  # name, wanted exit code, plan, extra args..., then -- and the expected substrings
  local name=$1 want=$2 plan=$3; shift 3
  local args=()
  while [ "$1" != "--" ]; do args+=("$1"); shift; done
  shift
  local out rc ok=1
  out=$("$acqd" --session "$tmp/$plan" "${args[@]}" 2>&1); rc=$?
  [ "$rc" -eq "$want" ] || ok=0
  for p in "$@"; do grep -qF -- "$p" <<<"$out" || ok=0; done
  if [ $ok -eq 1 ]; then
    passed=$((passed + 1)); echo "ok: $name"
  else
    failures=$((failures + 1)); echo "FAIL: $name (exit $rc, wanted $want and: $*)"; echo "$out" | tail -5
  fi
}

expect "good plan: dry run" 0 good.yaml --dry-run -- \
  "visiting order (collision-checked" "directions.tsv:8" "intrinsics              20 poses" \
  "board                   20 poses" "estimated capture time"
expect "wrong type" 1 bad_type.yaml --dry-run -- \
  "bad_type.yaml:10:42:" "gantry.axes.settle_s must be a number, not 'fast'"
expect "unknown key" 1 unknown_key.yaml --dry-run -- \
  "unknown_key.yaml:13:3:" "unknown key 'camera.exposure'" "the keys here are"
expect "unreachable direction" 1 unreachable.yaml --dry-run -- \
  "directions.tsv:7:" "camera zenith 63.000 deg exceeds the limit of 40.000"
expect "colliding direction" 1 colliding.yaml --dry-run -- \
  "directions.tsv:6:" "only 60.000 deg apart, the arms need 90.000"
expect "missing directions file" 1 missing_file.yaml --dry-run -- \
  "missing_file.yaml:15:9:" "no such file" "no-such-directions.tsv"
expect "missing validation directions file" 1 missing_validation.yaml --dry-run -- \
  "missing_validation.yaml:16:15:" "no such file" "no-such-validation.tsv" "leave directions.validation out"
expect "missing basis" 1 missing_basis.yaml --dry-run -- \
  "missing_basis.yaml:21:10:" "reconstruction.basis: no such file" "acq basis build"
expect "unknown backend" 1 unknown_backend.yaml --dry-run -- \
  "unknown_backend.yaml:3:10:" "unknown backend 'gpu'" "sim, usb+aravis or replay"
expect "two brackets" 1 two_brackets.yaml --dry-run -- \
  "two_brackets.yaml:13:" "both auto and bracket_us"
expect "broken YAML" 1 broken_yaml.yaml --dry-run -- \
  "broken_yaml.yaml:19:" "not valid YAML"
# The devices a usb+aravis plan names are not on this machine: opened before any motion, and
# the first one missing (the gantry) is named with what to check.
expect "backend not there" 1 absent_devices.yaml -- \
  "gantry USB 1209:acd0" "lsusb"
expect "sim without materials" 1 no_sim_materials.yaml --dry-run -- \
  "no_sim_materials.yaml:" "the sim backend needs sim.materials"
expect "unknown lens model" 1 bad_lensmodel.yaml --dry-run -- \
  "bad_lensmodel.yaml:18:14:" "unknown or unconfigured lens model 'LENSMODEL_OPENCV6'"
expect "intrinsics given twice" 1 both_intrinsics.yaml --dry-run -- \
  "both_intrinsics.yaml:18:17:" "exclude each other"
expect "directions given twice" 1 two_directions.yaml --dry-run -- \
  "two_directions.yaml:" "directions.file and directions.optimize exclude each other"
expect "no plan" 1 no_such_plan.yaml --dry-run -- "no_such_plan.yaml" "cannot read the plan"

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
