#!/usr/bin/env bash
# The pooled reconstruction against the independent one (issue 17, docs/reconstruction.md
# "Pooled"): `acq reconstruct synthetic --score` over fields of view, noise, forced numbers of
# groups, the centres' weighting to the plan's directions, a dropped view, 50 inks, a material
# covering 0.5% of the sample, and the blend, marbled and fine-text samples. Writes
# out/study/pooled/results.tsv and pooled.png.
# Needs out/main/basis116.acqb and out/main/optimized20.tsv (tools/run-main.sh). ~5 minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
acq=build/src/cli/acq
out=out/study/pooled
mkdir -p "$out"
source tools/main-inputs.sh  # basis, dirs
tsv="$out/results.tsv"
printf 'case\tfov_deg\tnoise\tmethod\tmedian\tseconds\tmaterials\n' >"$tsv"

# run CASE FOV NOISE METHOD [acq options...]: one reconstruction, one line of results.
run() {
  local name=$1 fov=$2 noise=$3 method=$4
  shift 4
  local log="$out/$name-$fov-$noise-$method.log"
  "$acq" reconstruct synthetic --basis "$basis" --fov-deg "$fov" --noise "$noise" \
    --method "$method" --score --quiet -o "$out/map.exr" "$@" >"$log" 2>&1
  local median seconds materials
  median=$(sed -n 's/.*RMSE against the ground truth: \([0-9.]*\).*/\1/p' "$log")
  seconds=$(sed -n 's/.*s solving, \([0-9.]*\) s in all.*/\1/p' "$log")
  materials=$(sed -n 's/^score: material \(.*\) median per-pixel log-space RMSE \([0-9.]*\);.*/\1=\2/p' \
    "$log" | paste -sd ';')
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$fov" "$noise" "$method" "$median" "$seconds" \
    "$materials" | tee -a "$tsv"
}

both() { for m in independent pooled; do run "$1" "$2" "$3" "$m" "${@:4}"; done; }

for fov in 0 4 10; do
  for noise in 0 0.05 0.1; do both card "$fov" "$noise" --directions "$dirs"; done
done
for g in 1 2 8 16; do run "groups-$g" 4 0.05 pooled --directions "$dirs" --groups "$g"; done
# The centres' weighting to the plan's directions (0: every pixel alike; default 0.15 deg).
for fov in 4 10; do
  for sigma in 0 0.05 0.5; do
    run "design-$sigma" "$fov" 0.05 pooled --directions "$dirs" --design-sigma-deg "$sigma"
  done
done
# One view dropped: the optimised set less its fifth direction.
awk 'NR != 6' "$dirs" >"$out/dropped19.tsv"
both one-view-dropped 4 0.05 --directions "$out/dropped19.tsv"
# 50 inks: the card's layout with 50 MERL materials.
inks=$(ls data/nbrdf/merl/*.h5 | head -50 | xargs -n1 basename | sed 's/\.h5$//' | paste -sd,)
both 50-inks 4 0.05 --directions "$dirs" --materials "$inks"
# A material covering 0.5% of the sample: a label image (white paint, a brass square).
/usr/bin/python3 - "$out/labels_half_percent.png" <<'EOF'
import sys, numpy as np, cv2
labels = np.zeros((256, 256), np.uint8)
labels[100:118, 140:158] = 1  # 324 pixels: 0.49% of 65536
cv2.imwrite(sys.argv[1], labels)
EOF
both half-percent 4 0.05 --directions "$dirs" --materials white-paint,brass \
  --sample-labels "$out/labels_half_percent.png"
for sample in blend marble text; do
  for fov in 0 4 10; do
    both "$sample" "$fov" 0.05 --directions "$dirs" --materials white-paint,brass --sample "$sample"
  done
done
/usr/bin/python3 - "$tsv" "$out/pooled.png" <<'EOF'
import sys, csv
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
def get(case, fov, noise, method, field="median"):
    for r in rows:
        if (r["case"], r["fov_deg"], r["noise"], r["method"]) == (case, fov, noise, method):
            return float(r[field])
    return float("nan")
fig, ax = plt.subplots(1, 6, figsize=(30, 4.5))
for method, style in (("independent", "o-"), ("pooled", "s-")):
    for noise in ("0", "0.05", "0.1"):
        ax[0].plot([0, 4, 10], [get("card", f, noise, method) for f in ("0", "4", "10")], style,
                   label=f"{method}, noise {noise}")
ax[0].set(xlabel="field of view (deg)", ylabel="median per-pixel log-space RMSE",
          title="card: error against the field of view")
ax[0].legend(fontsize=7)
cases = [("card 4 deg", "card", "4"), ("view dropped", "one-view-dropped", "4"),
         ("50 inks", "50-inks", "4"), ("0.5% material", "half-percent", "4")]
x = range(len(cases))
for i, method in enumerate(("independent", "pooled")):
    ax[1].bar([v + 0.4 * i for v in x], [get(c, f, "0.05", method) for _, c, f in cases], 0.4,
              label=method)
ax[1].set_xticks([v + 0.2 for v in x], [n for n, _, _ in cases], fontsize=8)
ax[1].set(title="stability at 4 deg, 5% noise")
ax[1].legend()
g = [1, 2, 8, 16]
ax[2].plot(g, [get(f"groups-{n}", "4", "0.05", "pooled") for n in g], "s-", label="forced")
ax[2].axhline(get("card", "4", "0.05", "pooled"), color="g", ls="--", label="chosen")
ax[2].axhline(get("card", "4", "0.05", "independent"), color="r", ls=":", label="independent")
ax[2].set(xscale="log", xlabel="groups forced", title="a wrong number of groups (4 deg, 5%)")
ax[2].legend()
samples = [(s, f) for s in ("blend", "marble", "text") for f in ("0", "4", "10")]
x = range(len(samples))
for i, method in enumerate(("independent", "pooled")):
    ax[3].bar([v + 0.4 * i for v in x], [get(s, f, "0.05", method) for s, f in samples], 0.4,
              label=method)
ax[3].set_xticks([v + 0.2 for v in x], [f"{s}\n{f} deg" for s, f in samples], fontsize=7)
ax[3].set(title="samples (5% noise)")
ax[3].legend()
sigmas = [0, 0.05, 0.15, 0.5]
for fov, style in (("4", "s-"), ("10", "o-")):
    ys = [get("card", fov, "0.05", "pooled") if s == 0.15 else get(f"design-{s}", fov, "0.05", "pooled")
          for s in sigmas]
    ax[4].plot([0.01 if s == 0 else s for s in sigmas], ys, style, label=f"{fov} deg")
    ax[4].axhline(get("card", fov, "0.05", "independent"), color="r" if fov == "4" else "m", ls=":",
                  label=f"independent, {fov} deg")
ax[4].set(xscale="log", xlabel="design weighting sigma (deg; 0 plotted at 0.01: every pixel alike)",
          title="the centres' weighting to the plan's directions (card, 5%)")
ax[4].legend(fontsize=7)
# Speed against accuracy (the card, 4 deg, 5%): every pixel alone, the chosen model, and each
# forced number of groups; the time is the whole reconstruction's (model, solve, scoring's read).
points = [("independent", "card", "independent"), ("pooled, chosen", "card", "pooled")] + \
         [(f"{n} groups", f"groups-{n}", "pooled") for n in g]
for label, case, method in points:
    t, e = get(case, "4", "0.05", method, "seconds"), get(case, "4", "0.05", method)
    ax[5].plot(t, e, "o" if method == "independent" else "s")
    ax[5].annotate(label, (t, e), fontsize=8, xytext=(4, 4), textcoords="offset points")
ax[5].set(xlabel="seconds, whole reconstruction (256 x 256)", ylabel="median per-pixel log-space RMSE",
          title="speed against accuracy (card, 4 deg, 5%)")
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=90)
print("wrote", sys.argv[2])
EOF
