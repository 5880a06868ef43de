#!/usr/bin/env bash
# What the normal search's settings trade through acqd (issue 19; docs/reconstruction.md,
# "Normals"). Each captured session (made by acqd with a relief, so that its ground truth scores
# the normals) is processed again from its reconstruction with the search off, on as planned,
# and on with each variant's settings; one CSV row per run (the relief's median error, the
# validation views' relative RMS, the refusals, the uncertainty's own figures), and a chart.
# usage: tools/study_normals_settings.sh OUT_DIR SESSION... -- VARIANT...
#   VARIANT: NAME:KEY=VALUE[,KEY=VALUE...], plan keys under reconstruction, e.g.
#   regrouped-e2:normals_confirm=regrouped,normals_evidence=2
#   (each run about 20 s for a 256 x 256 map on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { sed -n 2,10p "$0"; exit 1; }
out=$1; shift
sessions=() variants=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do sessions+=("$1"); shift; done
[ $# -gt 0 ] && { shift; variants=("$@"); }
mkdir -p "$out"
csv=$out/normals_settings.csv
# view1-3: relative RMS; median1-3: median per-pixel relative error; worst1-3: the share of the
# view's squared error from its worst pixel (one pixel can carry a view: docs/reconstruction.md);
# truth1-3: the map's render against the true materials' (the capture's noise and registration
# left out);
# floor1-3: the true materials' render against the capture (what no model of the sample removes).
echo "session,variant,search,relief_deg,flat_deg,map_log_rmse,view1,view2,view3,refused,median_uncertainty_deg,relief_certain_deg,relief_uncertain_deg,median1,median2,median3,worst1,worst2,worst3,truth1,truth2,truth3,floor1,floor2,floor3" > "$csv"
run() {  # session, variant's name, search (on | off), then acq session process options...
  local session=$1 variant=$2 search=$3; shift 3
  local dir
  dir=$(mktemp -d)
  build/src/cli/acq session process "$session" --from reconstruction "$@" -o "$dir/s" > "$dir/log" 2>&1 ||
    { cat "$dir/log"; exit 1; }
  /usr/bin/python3 - "$dir/s/report.json" "$(basename "$session")" "$variant" "$search" >> "$csv" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); n = r.get('normals', {})
def f(v): return '' if v is None else '%.4f' % v
def per_view(key, views=r['validation']):
    values = [f(v.get(key)) for v in views][:3]
    return values + [''] * (3 - len(values))
truth_views = r['ground_truth'].get('validation', [])
views = per_view('relative_rms')
print(','.join([sys.argv[2], sys.argv[3], sys.argv[4], f(n.get('median_error_deg_relief')),
                f(n.get('median_tilt_deg_flat')), f(r['ground_truth']['median_log_rmse'])] + views +
               [str(n.get('refused', '')), f(n.get('median_uncertainty_deg')),
                f(n.get('median_error_deg_relief_certain')),
                f(n.get('median_error_deg_relief_uncertain'))] +
               per_view('median_relative') + per_view('worst_pixel_share') +
               per_view('map_vs_truth_relative_rms', truth_views) +
               per_view('truth_vs_capture_relative_rms', truth_views)))
PY
  rm -rf "$dir"
  tail -1 "$csv"
}
for s in "${sessions[@]}"; do
  run "$s" off off --set reconstruction.normals=false
  run "$s" on on --set reconstruction.normals=true
  for v in "${variants[@]}"; do
    sets=()
    IFS=, read -ra pairs <<< "${v#*:}"
    for p in "${pairs[@]}"; do sets+=(--set "reconstruction.$p"); done
    run "$s" "${v%%:*}" on --set reconstruction.normals=true "${sets[@]}"
  done
done
/usr/bin/python3 tools/chart_normals_settings.py "$csv" "$out/normals_settings.png"
