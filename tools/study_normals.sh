#!/usr/bin/env bash
# The per-pixel normal search's study (issue 19; docs/reconstruction.md, "Normals"): the built-in
# embossed card (4 held-out materials, 128 x 128, 4 degree field of view, the seed paper's 20
# directions), reconstructed independently with and without --normals, over relief slopes and
# noise levels; and a glossy (brass) and a matte (white paint) card alone. Prints one CSV line per
# run and charts normal error and map error (tools/chart_normals.py).
# usage: tools/study_normals.sh BASIS OUT_DIR
set -euo pipefail
cd "$(dirname "$0")/.."
basis=$1 out=$2
mkdir -p "$out"
acq=build/src/cli/acq
csv=$out/normals.csv
echo "case,value,normals,map_error,normal_error_relief_deg,false_tilt_flat_deg,seconds" > "$csv"
run() {  # CASE VALUE ARGS...: one reconstruction with and one without the search
  local case=$1 value=$2; shift 2
  for normals in no yes; do
    local flag=()
    [ "$normals" = yes ] && flag=(--normals --normals-prior 2)
    local start=$(date +%s%N)
    local log
    log=$($acq reconstruct synthetic --basis "$basis" --directions data/directions/seed_directions_20.tsv \
      --size 128x128 --fov-deg 4 --method independent -o "$out/map.exr" --score --quiet "$@" "${flag[@]}" 2>&1)
    local ms=$((($(date +%s%N) - start) / 1000000))
    local seconds=$((ms / 1000)).$(printf %03d $((ms % 1000)))
    local err=$(sed -n 's/^score: median per-pixel log-space RMSE against the ground truth: \([0-9.]*\).*/\1/p' <<<"$log")
    local relief=$(sed -n 's/^score: normals: median angular error \([0-9.na]*\) deg.*/\1/p' <<<"$log")
    local flat=$(sed -n 's/.*median false tilt \([0-9.na]*\) deg.*/\1/p' <<<"$log")
    echo "$case,$value,$normals,$err,${relief:-nan},${flat:-nan},$seconds" | tee -a "$csv"
  done
}
for slope in 2 5 10 20; do run slope "$slope" --relief-deg "$slope"; done
for noise in 0.02 0.05 0.1; do run noise "$noise" --relief-deg 10 --noise "$noise"; done
run material brass --relief-deg 10 --materials brass
run material white-paint --relief-deg 10 --materials white-paint
run fibre 1 --relief-deg 10 --fibre-deg 1
/usr/bin/python3 tools/chart_normals.py "$csv" "$out/normals.png"
