#!/bin/sh
# The session benchmark (issue 8): a whole simulated session of the example plan from scratch
# (capture, processing, report), then where its time went and the daemon's own overhead as a
# share of it (report.txt), and a chart of the breakdown (out/bench/session/time.png).
#   tools/bench_session.sh [PLAN]   (default examples/plan-sim.yaml; needs its basis:
#                                    tools/run-main.sh builds out/main/basis90.acqb)
# Simulated time: the gantry runs at the plan's sim.time_scale, and the simulated camera renders
# a frame at once whatever its exposure, so motion and exposure are shorter than on the
# instrument; the daemon's overhead is real.
set -e
cd "$(dirname "$0")/.."
plan=${1:-examples/plan-sim.yaml}
out=out/bench/session
mkdir -p "$out"
session="$out/session"
rm -rf "$session"
sed "s#^output: .*#output: $(pwd)/$session#" "$plan" > "$out/plan.yaml"
# Relative paths in the plan are relative to its folder: rewrite them against the original's.
dir=$(cd "$(dirname "$plan")" && pwd)
sed -i "s#\.\./#$dir/../#g" "$out/plan.yaml"
build/src/daemon/acqd --session "$out/plan.yaml" --socket "$out/acqd.sock" > "$out/acqd.log"
cat "$session/report.txt"
/usr/bin/python3 - "$session/report.json" "$out/time.png" <<'PY'
import json, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
report = json.load(open(sys.argv[1]))
t = report["time_s"]
parts = ["motion", "exposure", "transfer", "bracket_probes", "operator", "hdr_merge", "calibration",
         "correspondence", "reconstruction", "validation", "scoring", "daemon_overhead"]
values = [max(t[p], 0) for p in parts]
fig, ax = plt.subplots(figsize=(8, 4))
ax.barh(parts, values)
ax.set_xlabel("seconds (wall %.1f s; planning the order %.1f s is part of the overhead)"
              % (t["wall"], t["planning"]))
ax.set_title("where a simulated session's time went (%s)" % report["plan"].split("/")[-1])
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=100)
print("chart:", sys.argv[2])
PY
