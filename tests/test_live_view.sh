#!/usr/bin/env bash
# The live view end to end (issue 23, docs/live-view.md): acqd on a simulated session with
# operator prompts, `acqctl serve` on a free port, and headless Chromium driving the page
# (tests/live_view.js); then the server's own bad cases (acqd never started, a port in use).
# usage: test_live_view.sh ACQD ACQCTL ACQ DATA_DIR SOURCE_ROOT
set -u
acqd=$1 acqctl=$2 acq=$3 data=$4 root=$5
puppeteer=$root/tools/node/node_modules/puppeteer-core
if [ ! -d "$puppeteer" ] || ! command -v chromium >/dev/null; then
  echo "the live view's test tools are not set up (chromium, tools/node): run tools/setup.sh"
  [ "${ACQ_REQUIRE_EXPORT_TOOLS:-0}" = 1 ] && exit 1
  exit 77
fi
tmp=$(mktemp -d)
pids=()
trap 'kill "${pids[@]}" 2>/dev/null; wait 2>/dev/null; rm -rf "$tmp"' EXIT
shots=${ACQ_LIVE_VIEW_SHOTS:-$tmp}
mkdir -p "$shots" "$tmp/run"
# The session test's operator plan (tests/test_session.cpp) and a small basis (three components
# of three materials: a second to build), enough for the processing the page shows.
"$acq" basis build "$data/nbrdf/merl/brass.h5" "$data/nbrdf/merl/white-paint.h5" \
  "$data/nbrdf/merl/black-fabric.h5" --components 3 -o "$tmp/basis.acqb" --quiet > /dev/null
cat > "$tmp/run/plan.yaml" <<PLAN
version: 1
backend: sim
output: session
sample: {size_mm: [40, 40]}
gantry:
  limits: {max_camera_zenith_deg: 66, max_light_zenith_deg: 89}
camera:
  hdr: {bracket_us: [2000, 16000]}
directions: {file: $data/directions/seed_directions_20.tsv, validation: $data/directions/validation_3.tsv}
calibration: {intrinsics_captures: 3, board: {size: [10, 10], spacing_mm: 3}}
spectralon: true
reconstruction: {basis: $tmp/basis.acqb, k: 3}
sim:
  materials: [$data/nbrdf/merl/white-paint.h5, $data/nbrdf/merl/brass.h5]
  time_scale: 20
  operator: true
PLAN
socket=$tmp/acqd.sock
failures=0
printed_url() {  # LOG: the address acqctl serve prints there, waited for up to 5 s
  for _ in $(seq 50); do
    grep -o 'http://[^ ]*' "$1" 2>/dev/null && return
    sleep 0.1
  done
}
"$acqd" --session "$tmp/run/plan.yaml" --socket "$socket" > "$tmp/acqd.log" 2>&1 &
pids+=($!)
"$acqctl" --socket "$socket" serve --port 0 > "$tmp/serve.log" 2>&1 &
pids+=($!)
url=$(printed_url "$tmp/serve.log")
if [ -z "$url" ]; then echo "FAIL: acqctl serve printed no address"; cat "$tmp/serve.log"; exit 1; fi
case "$url" in http://127.0.0.1:*) echo "ok: bound to 127.0.0.1 by default";; *) echo "FAIL: $url"; failures=$((failures + 1));; esac
node "$root/tests/live_view.js" "$puppeteer" "$url" "$shots" || { failures=$((failures + 1)); tail -20 "$tmp/acqd.log"; }

# The same plan without prompts, run to its end with the page open: the poses' thumbnails while
# it runs, the results once processed, kept after acqd ends; then a server given the finished
# session with no acqd at all.
kill "${pids[@]}" 2>/dev/null; wait 2>/dev/null; pids=()
mkdir -p "$tmp/whole" && sed 's/operator: true/operator: false/' "$tmp/run/plan.yaml" > "$tmp/whole/plan.yaml"
"$acqd" --session "$tmp/whole/plan.yaml" --socket "$socket" > "$tmp/whole.log" 2>&1 &
pids+=($!)
"$acqctl" --socket "$socket" serve --port 0 > "$tmp/serve3.log" 2>&1 &
pids+=($!)
url3=$(printed_url "$tmp/serve3.log")
node "$root/tests/live_view_results.js" "$puppeteer" "$url3" "$shots" running || { failures=$((failures + 1)); tail -20 "$tmp/whole.log"; }
kill "${pids[@]}" 2>/dev/null; wait 2>/dev/null; pids=()
"$acqctl" --socket "$tmp/none.sock" serve --port 0 --session "$tmp/whole/session" > "$tmp/serve4.log" 2>&1 &
pids+=($!)
url4=$(printed_url "$tmp/serve4.log")
node "$root/tests/live_view_results.js" "$puppeteer" "$url4" "$tmp" finished || failures=$((failures + 1))
out=$(timeout 5 "$acqctl" serve --port 0 --session "$tmp/no-such-session" 2>&1); rc=$?
if [ "$rc" -eq 1 ] && grep -qF "is not a folder" <<<"$out"; then echo "ok: --session that is not a folder is a clear error"
else echo "FAIL: --session not a folder (exit $rc): $out"; failures=$((failures + 1)); fi

# acqd --preview: the camera streaming to the page, the exposure from it; nothing recorded.
kill "${pids[@]}" 2>/dev/null; wait 2>/dev/null; pids=()
mkdir -p "$tmp/preview" && cp "$tmp/run/plan.yaml" "$tmp/preview/plan.yaml"
"$acqd" --session "$tmp/preview/plan.yaml" --preview --socket "$socket" > "$tmp/preview.log" 2>&1 &
pids+=($!)
"$acqctl" --socket "$socket" serve --port 0 > "$tmp/serve2.log" 2>&1 &
pids+=($!)
url2=$(printed_url "$tmp/serve2.log")
node "$root/tests/live_view_preview.js" "$puppeteer" "$url2" "$shots" || { failures=$((failures + 1)); tail -20 "$tmp/preview.log"; }
if [ -n "$(ls -A "$tmp/preview/session/frames" 2>/dev/null)" ]; then
  echo "FAIL: the preview recorded frames"; failures=$((failures + 1))
else
  echo "ok: the preview recorded nothing"
fi

# The server's own bad cases.
port=$(sed -E 's|.*:([0-9]+)/.*|\1|' <<<"$url2")  # the preview's server, still running
out=$(timeout 5 "$acqctl" --socket "$tmp/none.sock" serve --port "$port" 2>&1); rc=$?
if [ "$rc" -eq 1 ] && grep -qF "cannot listen" <<<"$out"; then echo "ok: a port in use is a clear error"
else echo "FAIL: a port in use (exit $rc): $out"; failures=$((failures + 1)); fi
out=$(timeout 5 "$acqctl" serve --bind 0.0.0.0 --port 0 2>&1); rc=$?
if grep -qF "beyond this machine" <<<"$out"; then echo "ok: binding beyond localhost is said"
else echo "FAIL: no warning for --bind 0.0.0.0: $out"; failures=$((failures + 1)); fi
echo "$failures failed"
[ "$failures" -eq 0 ]
