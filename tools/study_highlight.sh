#!/usr/bin/env bash
# What limits the validation view nearest the highlight (issue 16; docs/colour.md, "The view
# nearest the highlight"): a simulated session's validation view predicted by each true
# material's homogeneous, noise-free reconstruction at the sample's centre (the method's own
# floor there), against the truth, in CIEDE2000 per material; tools/study_highlight.py says how.
# Needs the renderers' environment (tools/setup.sh --viewers) for its EXR reader.
# usage: tools/study_highlight.sh [SESSION] [VIEW] [BASIS] [DIRECTIONS]
#   (defaults: out/sessions/sim-card, 2 (validation_3.tsv:8, the near-specular one),
#   out/main/basis116.acqb, data/directions/seed_directions_20.tsv: the main job's)
set -euo pipefail
cd "$(dirname "$0")/.."
session=${1:-out/sessions/sim-card} view=${2:-2}
basis=${3:-out/main/basis116.acqb} directions=${4:-data/directions/seed_directions_20.tsv}
acq=build/src/cli/acq
[ -f "$session/renders/validation_$(printf %03d "$view").exr" ] ||
  { echo "$session has no kept validation data for view $view (run tools/run-main.sh first)"; exit 1; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cp "$session/ground_truth/materials.tsv" "$out/"
.venv/bin/python tools/study_highlight.py dump "$session" "$view" "$out"
for name in $(grep -v '^#' "$session/ground_truth/materials.tsv" | cut -f2); do
  $acq reconstruct synthetic --basis "$basis" --directions "$directions" --materials "$name" \
    --fov-deg 0 --size 8x8 -o "$out/$name.exr" --quiet > /dev/null
  $acq render export --map "$out/$name.exr" --basis "$basis" --pixel 4,4 -o "$out/$name.binary" > /dev/null
done
echo "== the homogeneous reconstruction looked up at the nearest bin"
/usr/bin/python3 tools/study_highlight.py floor "$out" "$out"
echo "== the same, interpolated between bins along theta_h"
/usr/bin/python3 tools/study_highlight.py floor "$out" "$out" --interpolated
