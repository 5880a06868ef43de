#!/usr/bin/env bash
# The per-pixel normal search's study (issue 19; docs/reconstruction.md, "Normals"): the built-in
# embossed card (4 held-out materials, 128 x 128, 4 degree field of view, the seed paper's 20
# directions), reconstructed independently without the search ("none"), with the search scored by
# each pixel's own fit ("fit", the first criterion), by its material group's centre alone
# ("one-centre"), by its groups' centres or two of them mixed ("centre", the default) and the same
# with every view scored ("untrimmed": none of the worst-explained left out), over relief slopes
# and noise levels; single materials (a glossy brass, a matte
# white paint, a dark fabric, a mirror-like chrome) with a raised border; and the card through
# the pooled reconstruction. Prints one CSV line per run and charts normal error, false tilt and
# map error (tools/chart_normals.py). Then the search methods' price: the embossed card at
# 256 x 256 with 2% noise searched by each method and depth, the search's own time against its
# normal error (search.csv, chart search.png).
# usage: tools/study_normals.sh BASIS OUT_DIR
set -euo pipefail
cd "$(dirname "$0")/.."
basis=$1 out=$2
mkdir -p "$out"
acq=build/src/cli/acq
csv=$out/normals.csv
echo "case,value,search,map_error,normal_error_relief_deg,false_tilt_flat_deg,refused,no_evidence,seconds" > "$csv"
# Figures read from `acq reconstruct synthetic --score`'s log on stdin (one place for its format).
map_error() { sed -n 's/^score: median per-pixel log-space RMSE against the ground truth: \([0-9.]*\).*/\1/p'; }
normal_error() { sed -n 's/^score: normals: median angular error \([0-9.na]*\) deg.*/\1/p'; }
false_tilt() { sed -n 's/.*median false tilt \([0-9.na]*\) deg.*/\1/p'; }
run() {  # CASE VALUE ARGS...: one reconstruction per search
  local case=$1 value=$2; shift 2
  for search in none fit one-centre centre untrimmed; do
    local flag=()
    case $search in
      none) ;;
      one-centre) flag=(--normals --normals-criterion centre --normals-single-centre) ;;
      untrimmed) flag=(--normals --normals-criterion centre --normals-trimmed-views 0) ;;
      *) flag=(--normals --normals-criterion "$search") ;;
    esac
    local start=$(date +%s%N)
    local log
    log=$($acq reconstruct synthetic --basis "$basis" --directions data/directions/seed_directions_20.tsv \
      --size 128x128 --fov-deg 4 -o "$out/map.exr" --score --quiet "$@" "${flag[@]}" 2>&1)
    local ms=$((($(date +%s%N) - start) / 1000000))
    local seconds=$((ms / 1000)).$(printf %03d $((ms % 1000)))
    local err=$(map_error <<<"$log") relief=$(normal_error <<<"$log") flat=$(false_tilt <<<"$log")
    local refused=$(sed -n 's/^normals: [0-9]* estimated, \([0-9]*\) refused.*/\1/p' <<<"$log")
    local none=$(sed -n 's/^normals: .* refused, \([0-9]*\) without evidence.*/\1/p' <<<"$log")
    echo "$case,$value,$search,$err,${relief:-nan},${flat:-nan},${refused:-0},${none:-0},$seconds" | tee -a "$csv"
  done
}
# 40: steeper than the search's 25 degree cone, where it must refuse (the refused column).
for slope in 2 5 10 20 40; do run slope "$slope" --method independent --relief-deg "$slope"; done
for noise in 0.02 0.05 0.1; do run noise "$noise" --method independent --relief-deg 10 --noise "$noise"; done
for m in brass white-paint black-fabric chrome; do
  run material "$m" --method independent --relief-deg 10 --materials "$m"
done
run flat card --method independent --relief-deg 0.01
run pooled card --relief-deg 10
run pooled flat-card --relief-deg 0.01

search_csv=$out/search.csv
echo "method,levels,coarse_reach,search_seconds,normal_error_relief_deg,one_material_deg,ink_edges_deg,false_tilt_flat_deg,map_error" > "$search_csv"
search() {  # METHOD LEVELS REACH: one reconstruction of the 256 x 256 card
  local log
  log=$($acq reconstruct synthetic --basis "$basis" --directions data/directions/seed_directions_20.tsv \
    --size 256x256 --fov-deg 4 --relief-deg 10 --noise 0.02 -o "$out/map.exr" --score --quiet --normals \
    --normals-search "$1" --normals-levels "$2" --normals-coarse-reach "$3" 2>&1)
  local seconds=$(sed -n 's/^normals: .* \([0-9.]*\) s$/\1/p' <<<"$log")
  local one=$(sed -n 's/.*flat; \([0-9.na]*\) over [0-9]* of one material.*/\1/p' <<<"$log")
  local edges=$(sed -n 's/.*of one material, \([0-9.na]*\) over .*/\1/p' <<<"$log")
  local relief=$(normal_error <<<"$log") flat=$(false_tilt <<<"$log") err=$(map_error <<<"$log")
  echo "$1,$2,$3,$seconds,$relief,$one,$edges,$flat,$err" | tee -a "$search_csv"
}
for levels in 3 4 5 6; do search grid "$levels" 1; done
search grid 6 2
for levels in 3 4 5; do search quadratic "$levels" 1; done
/usr/bin/python3 tools/chart_normals.py "$csv" "$out/normals.png" "$search_csv" "$out/search.png"
