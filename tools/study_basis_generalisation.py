#!/usr/bin/python3
"""How a basis does on materials it never saw (issue 18, item 3): k-fold cross-validation over
the MERL and RGL-EPFL fits (data/nbrdf/merl, data/nbrdf/rgl). For each fold, two bases are
built from the other folds' materials: MERL+RGL, and MERL alone (the paper's setting; its RGL
scores are then of materials no MERL-only basis ever sees). Every material of the fold is
reconstructed from its values at the directions (`acq basis eval`, ridge k and eta) and scored
by log-space RMSE per channel. No material is ever scored by a basis that trained on it
(`acq basis eval` would warn; the study fails if it does).

Folds: each source's materials, sorted by name, dealt round-robin into K folds (the same folds
for both bases). Families: RGL's by name prefix (acrylic_felt, cc, cg, ...; the colour-shifting
and flake paints are cc_, cg_, chm_, cm_, irid_flake_, vch_), MERL's by the kind its name ends
in (paint, metallic-paint, fabric, plastic, phenolic, rubber, acrylic, metal, wood, stone, other).

Writes OUT/per_material.csv, OUT/summary.txt (overall, per source, per family: median over
channels, mean, worst material) and OUT/by_family.png.

  tools/study_basis_generalisation.py [--folds 5] [--k 20] [--eta 40]
      [--directions data/directions/seed_directions_20.tsv] [--out DIR]"""
import argparse
import csv
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SOURCES = {"merl": os.path.join(ROOT, "data", "nbrdf", "merl"),
           "rgl": os.path.join(ROOT, "data", "nbrdf", "rgl")}
RGL_FAMILIES = ["acrylic_felt", "irid_flake", "colodur", "aurora", "paper", "satin", "leaf",
                "ilm", "vch", "chm", "cc", "cg", "cm"]
MERL_KINDS = [("metallic-paint", "metallic-paint"), ("paint", "paint"), ("fabric", "fabric"),
              ("felt", "fabric"), ("phenolic", "phenolic"), ("plastic", "plastic"),
              ("rubber", "rubber"), ("acrylic", "acrylic"),
              ("steel", "metal"), ("bronze", "metal"), ("aluminium", "metal"), ("brass", "metal"),
              ("chrome", "metal"), ("nickel", "metal"), ("gold", "metal"), ("silver", "metal"),
              ("tungsten", "metal"), ("ss440", "metal"), ("hematite", "metal"),
              ("maple", "wood"), ("oak", "wood"), ("pine", "wood"), ("walnut", "wood"),
              ("cherry", "wood"), ("fruitwood", "wood"), ("natural", "wood"),
              ("marble", "stone"), ("jasper", "stone"), ("obsidian", "stone"),
              ("aventurnine", "stone")]
COLOUR_SHIFTING = {"cc", "cg", "chm", "cm", "irid_flake", "vch"}


def family(source, name):
    if source == "rgl":
        for f in RGL_FAMILIES:
            if name.startswith(f + "_"):
                return "rgl:" + f + (" (colour-shifting)" if f in COLOUR_SHIFTING else "")
        return "rgl:other"
    for key, kind in MERL_KINDS:
        if key in name:
            return "merl:" + kind
    return "merl:other"


def materials():
    out = []  # (source, name, path)
    for source, folder in SOURCES.items():
        for f in sorted(os.listdir(folder)):
            if f.endswith(".h5"):
                out.append((source, f[:-3], os.path.join(folder, f)))
    return out


def run(cmd):
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"study: {' '.join(cmd)} failed:\n{res.stdout[-2000:]}\n{res.stderr[-2000:]}")
    return res


def build(acq, paths, out):
    run([acq, "basis", "build", *paths, "-o", out, "--quiet"])


def evaluate(acq, basis, paths, a, csv_path):
    res = run([acq, "basis", "eval", "--basis", basis, "--directions", a.directions, "--k",
               str(a.k), "--eta", str(a.eta), "--all-given", "--csv", csv_path, *paths])
    if "trained this basis" in res.stderr:
        sys.exit("study: a material was scored by a basis that trained on it:\n" + res.stderr)
    scores = {}
    with open(csv_path) as f:
        for row in csv.DictReader(f):
            scores.setdefault(row["material"], []).append(float(row["log_rmse"]))
    return scores


def summarise(rows, key):
    """rows: dicts with 'channels' (log RMSE per channel) and the grouping key."""
    groups = {}
    for r in rows:
        groups.setdefault(key(r), []).append(r)
    lines = []
    for g in sorted(groups):
        rs = groups[g]
        channels = [c for r in rs for c in r["channels"]]
        per_material = [statistics.mean(r["channels"]) for r in rs]
        worst = max(rs, key=lambda r: statistics.mean(r["channels"]))
        lines.append((g, len(rs), statistics.median(channels), statistics.mean(per_material),
                      statistics.mean(worst["channels"]), worst["name"]))
    return lines


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--folds", type=int, default=5)
    ap.add_argument("--k", type=int, default=20)
    ap.add_argument("--eta", type=float, default=40)
    ap.add_argument("--directions",
                    default=os.path.join(ROOT, "data", "directions", "seed_directions_20.tsv"))
    ap.add_argument("--out", help="default out/study/basis_cv_k{K}_eta{ETA}")
    a = ap.parse_args()
    if not a.out:
        a.out = os.path.join(ROOT, "out", "study", f"basis_cv_k{a.k}_eta{a.eta:g}")
    acq = os.path.join(a.build, "src", "cli", "acq")
    os.makedirs(a.out, exist_ok=True)
    all_materials = materials()
    fold_of = {}
    for source in SOURCES:
        names = [m for m in all_materials if m[0] == source]
        for i, m in enumerate(names):
            fold_of[m] = i % a.folds
    rows = []
    for fold in range(a.folds):
        test = [m for m in all_materials if fold_of[m] == fold]
        train_all = [m[2] for m in all_materials if fold_of[m] != fold]
        train_merl = [m[2] for m in all_materials if fold_of[m] != fold and m[0] == "merl"]
        for basis_name, train in (("merl+rgl", train_all), ("merl", train_merl)):
            basis = os.path.join(a.out, f"fold{fold}_{basis_name}.acqb")
            build(acq, train, basis)
            scores = evaluate(acq, basis, [m[2] for m in test], a,
                              os.path.join(a.out, f"fold{fold}_{basis_name}.csv"))
            os.remove(basis)  # 300-400 MB each
            for source, name, _ in test:
                rows.append({"basis": basis_name, "fold": fold, "source": source, "name": name,
                             "family": family(source, name), "channels": scores[name]})
        print(f"fold {fold + 1} of {a.folds}: {len(test)} materials scored", flush=True)

    with open(os.path.join(a.out, "per_material.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["basis", "fold", "source", "family", "material", "log_rmse_R", "log_rmse_G",
                    "log_rmse_B"])
        for r in rows:
            w.writerow([r["basis"], r["fold"], r["source"], r["family"], r["name"],
                        *[f"{c:.5f}" for c in r["channels"]]])
    text = [f"k-fold cross-validation ({a.folds} folds), directions {a.directions}, k = {a.k}, "
            f"eta = {a.eta}; log-space RMSE of materials no basis trained on",
            "columns: materials, median over their channels, mean over materials, worst material"]
    for title, key in (("overall", lambda r: r["basis"]),
                       ("per source", lambda r: (r["basis"], r["source"])),
                       ("per family", lambda r: (r["family"], r["basis"]))):
        text.append(f"\n{title}:")
        for g, n, med, mean, worst, worst_name in summarise(rows, key):
            label = " / ".join(g) if isinstance(g, tuple) else g
            text.append(f"  {label:<44} {n:4d} {med:7.4f} {mean:7.4f} {worst:7.4f} ({worst_name})")
    open(os.path.join(a.out, "summary.txt"), "w").write("\n".join(text) + "\n")
    print("\n".join(text))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fams = sorted({r["family"] for r in rows})
        fig, ax = plt.subplots(figsize=(10, 0.32 * len(fams) + 1.5))
        for j, b in enumerate(("merl", "merl+rgl")):
            med = []
            for fam in fams:
                ch = [c for r in rows if r["family"] == fam and r["basis"] == b for c in r["channels"]]
                med.append(statistics.median(ch))
            ax.barh([i + 0.4 * j for i in range(len(fams))], med, height=0.4, label=b + " basis")
        ax.set_yticks([i + 0.2 for i in range(len(fams))], fams)
        ax.set_xlabel("median log-space RMSE over the family's channels (cross-validated)")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "by_family.png"), dpi=100)
    except ImportError:
        print("(matplotlib missing: no chart)")


if __name__ == "__main__":
    main()
