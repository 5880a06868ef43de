#!/bin/sh
# The session benchmark (issues 8, 21): a whole simulated session of the example plan from
# scratch (capture, processing, report), then where its time went and the daemon's own overhead
# as a share of it (report.txt), the figures below, and a chart of the breakdown
# (OUT/time.png).
#   [ACQD=path/to/acqd] tools/bench_session.sh [--full-size] [PLAN]
#     PLAN         default examples/plan-sim-mono.yaml (the mono camera: the figures of issue 21
#                  were measured with it); needs its basis (tools/run-main.sh builds
#                  out/main/basis116.acqb)
#     --full-size  the simulated camera at 2048 x 2048 and the gantry at real speed
#                  (sim.image_size [2048, 2048], sim.time_scale 1): the full-size session of
#                  issue 21, into out/bench/session-full
# Figures: frames per second sustained while framing (frames over exposure and transfer time),
# frames that arrived incomplete, the daemon's overhead as a share of the session, peak memory
# (GNU time), and the time from the last frame to the processed session.
# The simulated camera renders a frame at once whatever its exposure, so exposure is shorter
# than on the instrument; at the default sim.time_scale the motion is too. The overhead is real.
set -e
cd "$(dirname "$0")/.."
full=0
if [ "$1" = "--full-size" ]; then full=1; shift; fi
plan=${1:-examples/plan-sim-mono.yaml}
out=out/bench/session
[ $full = 1 ] && out=out/bench/session-full
mkdir -p "$out"
session="$out/session"
rm -rf "$session"
sed "s#^output: .*#output: $(pwd)/$session#" "$plan" > "$out/plan.yaml"
# Relative paths in the plan are relative to its folder: rewrite them against the original's.
dir=$(cd "$(dirname "$plan")" && pwd)
sed -i "s#\.\./#$dir/../#g" "$out/plan.yaml"
if [ $full = 1 ]; then
  # A 2048 x 2048 frame is 8 MiB; the driver asks for a 32 MiB receive buffer, which the kernel
  # caps at net.core.rmem_max: raised where we may (root), as tools/bench_camera.sh does.
  if [ "$(id -u)" = 0 ]; then sysctl -qw net.core.rmem_max=33554432; fi
  echo "net.core.rmem_max = $(cat /proc/sys/net/core/rmem_max)"
  sed -i -e 's#^\( *time_scale:\).*#\1 1#' -e 's#^sim:.*#sim:\n  image_size: [2048, 2048]#' \
    "$out/plan.yaml"
fi
/usr/bin/time -v -o "$out/time.txt" \
  "${ACQD:-build/src/daemon/acqd}" --session "$out/plan.yaml" --socket "$out/acqd.sock" > "$out/acqd.log"
cat "$session/report.txt"
/usr/bin/python3 - "$session/report.json" "$out/time.txt" "$out/time.png" <<'PY'
import json, re, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
report = json.load(open(sys.argv[1]))
t, frames = report["time_s"], report["frames"]
peak_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)",
                        open(sys.argv[2]).read()).group(1))
framing_s = t["exposure"] + t["transfer"]
print("\nfigures:")
print("  frames taken %d, at %.2f frames/s while framing (%.1f s of exposure and transfer); "
      "%d arrived incomplete, %d retaken"
      % (frames["taken"], frames["taken"] / framing_s, framing_s, frames["incomplete"],
         frames["retaken"]))
print("  daemon overhead %.2f s, %.2f%% of the session's %.1f s"
      % (t["daemon_overhead"], 100 * t["daemon_overhead"] / t["wall"], t["wall"]))
print("  peak memory %.0f MB" % (peak_kb / 1024))
print("  from the last frame to the processed session (map and validation renders): %.1f s"
      % t["after_capture"])
parts = ["motion", "exposure", "transfer", "bracket_probes", "operator", "hdr_merge", "calibration",
         "correspondence", "reconstruction", "validation", "scoring", "daemon_overhead"]
values = [max(t[p], 0) for p in parts]
fig, ax = plt.subplots(figsize=(8, 4))
ax.barh(parts, values)
ax.set_xlabel("seconds (wall %.1f s; planning the order %.1f s is part of the overhead)"
              % (t["wall"], t["planning"]))
ax.set_title("where a simulated session's time went (%s, %d x %d map)"
             % (report["plan"].split("/")[-2], report["map"]["width"], report["map"]["height"]))
fig.tight_layout()
fig.savefig(sys.argv[3], dpi=100)
print("chart:", sys.argv[3])
PY
