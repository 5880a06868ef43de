#!/usr/bin/env bash
# The pooled reconstruction against the independent one on cards of other materials than the
# four its rules were tuned on (issue 17, docs/reconstruction.md "Cards of other materials"): for
# each seed, four materials drawn at random from the MERL fits and four from the RGL-EPFL fits,
# laid out as the built-in card, 4 degree field of view, 5% noise, the main job's optimised
# directions. Most drawn materials are in the basis's training set (it holds out ten MERL
# materials): the absolute errors flatter the basis; the two solves' ratio is what this tests. Writes
# out/study/random_cards/results.tsv (one line per material) and cards.png (each material's
# pooled error against its independent one).
# Usage: tools/study_random_cards.sh [SEED...] (default 1 2 3 4 5; ~1 minute a seed).
# Needs out/main/basis116.acqb and out/main/optimized20.tsv (tools/run-main.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
acq=build/src/cli/acq
out=out/study/random_cards
mkdir -p "$out"
source tools/main-inputs.sh  # basis, dirs
seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(1 2 3 4 5)
tsv="$out/results.tsv"
printf 'set\tseed\tmaterial\tindependent\tpooled\n' >"$tsv"
for seed in "${seeds[@]}"; do
  for set in merl rgl; do
    materials=$(ls data/nbrdf/$set/*.h5 | xargs -n1 basename | sed 's/\.h5$//' |
      /usr/bin/python3 -c "import sys, random
print(','.join(random.Random($seed).sample(sys.stdin.read().split(), 4)))")
    for method in independent pooled; do
      "$acq" reconstruct synthetic --basis "$basis" --directions "$dirs" --fov-deg 4 \
        --noise 0.05 --seed "$seed" --method "$method" --materials-dir "data/nbrdf/$set" \
        --materials "$materials" --score --quiet -o "$out/map.exr" \
        >"$out/$set-$seed-$method.log" 2>&1
    done
    # One line per material: its median error by each method.
    join <(sed -n 's/^score: material \([^ ]*\) median per-pixel log-space RMSE \([0-9.]*\);.*/\1 \2/p' \
      "$out/$set-$seed-independent.log" | sort) \
      <(sed -n 's/^score: material \([^ ]*\) median per-pixel log-space RMSE \([0-9.]*\);.*/\1 \2/p' \
        "$out/$set-$seed-pooled.log" | sort) |
      awk -v set="$set" -v seed="$seed" '{printf "%s\t%s\t%s\t%s\t%s\n", set, seed, $1, $2, $3}' |
      tee -a "$tsv"
  done
done
/usr/bin/python3 - "$tsv" "$out/cards.png" <<'PY'
import sys, csv
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
fig, ax = plt.subplots(figsize=(5.5, 5))
for s, marker in (("merl", "o"), ("rgl", "s")):
    sel = [r for r in rows if r["set"] == s]
    ax.scatter([float(r["independent"]) for r in sel], [float(r["pooled"]) for r in sel],
               marker=marker, label=f"{s} ({len(sel)} materials)")
top = max(max(float(r["independent"]), float(r["pooled"])) for r in rows) * 1.05
ax.plot([0, top], [0, top], "k:", label="equal")
ax.set(xlabel="independent: median per-pixel log-space RMSE",
       ylabel="pooled", title="random 4-material cards, 4 deg, 5% noise", xlim=(0, top),
       ylim=(0, top))
ax.legend()
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)
worse = [r for r in rows if float(r["pooled"]) > float(r["independent"])]
print(f"{len(rows)} materials; pooled worse on {len(worse)}:",
      ", ".join(f"{r['material']} {r['independent']} -> {r['pooled']}" for r in worse) or "none")
PY
