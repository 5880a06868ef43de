#!/usr/bin/env bash
# Does the live view slow the capture? (issue 23; docs/live-view.md) The same simulated session
# (the test plan's, 8 intrinsics boards; its wall time to the end of the capture) run RUNS times
# in each of three ways, in turn: without a page ("none"); with the page open in headless
# Chromium ("page"); and with the page's requests replayed on the page's schedule by a client
# that is not a browser ("requests", tools/live_view_requests.js), which measures what the
# requests cost acqd and `acqctl serve` apart from a browser's own work on this machine; and with
# the same browser open on an empty page ("browser"), what a browser costs by itself. For each
# client the CPU seconds it used (the browser's processes, or node's) are printed; and
# `acqctl status`'s latency during the capture.
# usage: tools/bench_live_view.sh [RUNS]   (default 2; prints a table; BENCH_LIVE_VIEW_WAYS="none
# page" runs only those; BENCH_LIVE_VIEW_TIME_SCALE=1 runs the gantry's motion at its real speed
# instead of the default 20 times faster, which makes the camera's simulation the bottleneck)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-2}
acqd=build/src/daemon/acqd acqctl=build/src/daemon/acqctl acq=build/src/cli/acq
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
$acq basis build data/nbrdf/merl/brass.h5 data/nbrdf/merl/white-paint.h5 \
  data/nbrdf/merl/black-fabric.h5 --components 3 -o "$tmp/basis.acqb" --quiet > /dev/null
plan() {  # DIR: the plan, capture and processing (the processing is the same either way)
  mkdir -p "$1"
  sed "s|BASIS|$tmp/basis.acqb|; s|DATA|$PWD/data|g; s|TIME_SCALE|${BENCH_LIVE_VIEW_TIME_SCALE:-20}|" > "$1/plan.yaml" <<'PLAN'
version: 1
backend: sim
output: session
sample: {size_mm: [40, 40]}
gantry:
  limits: {max_camera_zenith_deg: 66, max_light_zenith_deg: 89}
camera:
  hdr: {bracket_us: [2000, 16000]}
directions: {file: DATA/directions/seed_directions_20.tsv, validation: DATA/directions/validation_3.tsv}
calibration: {intrinsics_captures: 8, board: {size: [10, 10], spacing_mm: 3}}
spectralon: true
reconstruction: {basis: BASIS, k: 3}
sim:
  materials: [DATA/nbrdf/merl/white-paint.h5, DATA/nbrdf/merl/brass.h5]
  time_scale: TIME_SCALE
PLAN
}
capture_s() {  # LOG: the capture's wall time, from acqd's "processing" line
  grep -m1 -oE '^\[ *[0-9.]+ s\] processing' "$1" | grep -oE '[0-9.]+'
}
printf "run  page      capture_s  client_cpu_s  status_ms(median, max)\n"
for r in $(seq "$runs"); do
  for page in ${BENCH_LIVE_VIEW_WAYS:-none page requests browser}; do
    d=$tmp/$r-$page; plan "$d"
    sock=$tmp/$r-$page.sock
    $acqd --session "$d/plan.yaml" --socket "$sock" > "$d/acqd.log" 2>&1 &
    acqd_pid=$!
    latency=""
    if [ $page != none ]; then
      $acqctl --socket "$sock" serve --port 0 > "$d/serve.log" 2>&1 &
      serve_pid=$!
      sleep 0.5
      url=$(grep -o 'http://[^ ]*' "$d/serve.log")
      # The client's CPU seconds, its children (the browser's processes) included.
      client=(node tools/live_view_requests.js "$url")
      puppeteer=$PWD/tools/node/node_modules/puppeteer-core
      [ $page = page ] && client=(node tools/live_view_watch.js "$puppeteer" "$url")
      [ $page = browser ] && client=(node tools/live_view_watch.js "$puppeteer" "$url" --blank)
      /usr/bin/time -f "%U %S" -o "$d/client_cpu" "${client[@]}" > "$d/page.log" 2>&1 &
      page_pid=$!
    fi
    # acqctl status's latency (process start included) during the capture, page or none.
    sleep 5
    for _ in $(seq 20); do
      s=$(date +%s%N); $acqctl --socket "$sock" status > /dev/null 2>&1 || true; e=$(date +%s%N)
      latency="$latency $(( (e - s) / 1000000 ))"; sleep 0.2
    done
    wait $acqd_pid || true
    client_cpu=""
    if [ $page != none ]; then
      # The client ends when it sees the session end (or acqd gone); the server goes after it.
      for _ in $(seq 60); do kill -0 $page_pid 2>/dev/null || break; sleep 0.5; done
      kill $page_pid 2>/dev/null || true
      wait $page_pid 2>/dev/null || true
      kill $serve_pid 2>/dev/null || true
      client_cpu=$(awk '{print $1 + $2}' "$d/client_cpu" 2>/dev/null || true)
    fi
    stats=""
    [ -n "$latency" ] && stats=$(tr ' ' '\n' <<<"$latency" | sed '/^$/d' | sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)] ", " a[NR]}')
    printf "%-4s %-9s %-10s %-13s %s\n" "$r" "$page" "$(capture_s "$d/acqd.log")" "${client_cpu:--}" "$stats"
  done
done
