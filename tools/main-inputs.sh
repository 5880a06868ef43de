# Sourced (from the repository root) by the studies that run on the main job's outputs: sets
# basis and dirs, the default basis and the optimised directions that tools/run-main.sh builds,
# and stops with what to do when either is missing.
basis=out/main/basis116.acqb
dirs=out/main/optimized20.tsv
for f in "$basis" "$dirs"; do
  [ -f "$f" ] || { echo "$(basename "$0"): $f is missing: run tools/run-main.sh first" >&2; exit 1; }
done
