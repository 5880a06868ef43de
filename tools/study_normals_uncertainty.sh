#!/usr/bin/env bash
# How well the data fix a normal, and what refusing the uncertain ones trades (issue 19;
# docs/reconstruction.md, "How well the data fix a normal"): tools/study_normals_settings.sh with
# one variant a limit of reconstruction.normals_max_uncertainty_deg, each named by its degrees.
# usage: tools/study_normals_uncertainty.sh OUT_DIR SESSION... [-- LIMIT...]
#   (limits default 13 6 3 1.5 degrees)
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 2 ] || { sed -n 2,6p "$0"; exit 1; }
out=$1; shift
sessions=() limits=(13 6 3 1.5)
while [ $# -gt 0 ] && [ "$1" != -- ]; do sessions+=("$1"); shift; done
[ $# -gt 0 ] && { shift; limits=("$@"); }
variants=()
for l in "${limits[@]}"; do variants+=("$l:normals_max_uncertainty_deg=$l"); done
exec tools/study_normals_settings.sh "$out" "${sessions[@]}" -- "${variants[@]}"
