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

Directions (item 4): the given set (default the seed's 20) for every fold, and with --optimise
also 20 directions optimised for each fold's basis by `acq directions optimize` (the same
optimiser, k and eta for both bases), so that each basis is scored with directions chosen for it.
With --fov-deg 0,4,10, each fold's held-out materials are also scored over those fields of view
(`acq directions eval`: each position its own rows); its table is the mean over folds of each
fold's median.

Writes OUT/per_material.csv, OUT/summary.txt (overall, per source, per family: median over
channels, mean, worst material; per direction set) and OUT/by_family.png, and with --fov-deg
OUT/fov.csv and a table in the summary.

  tools/study_basis_generalisation.py [--folds 5] [--k 20] [--eta 40]
      [--directions data/directions/seed_directions_20.tsv] [--optimise] [--fov-deg 0,4,10]
      [--out DIR]"""
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


def optimise(acq, basis, a, tsv):
    run([acq, "directions", "optimize", "--basis", basis, "--n", str(a.n), "--k", str(a.k),
         "--eta", str(a.eta), "-o", tsv, "--quiet"])


def evaluate_fov(acq, basis, directions, paths, a, csv_path):
    """Per field of view: the median over the held-out channels of the position-averaged error,
    and the worst condition number over the positions."""
    run([acq, "directions", "eval", "--basis", basis, "--directions", directions, "--k",
         str(a.k), "--eta", str(a.eta), "--fov-deg", a.fov_deg, "--csv", csv_path, "--label",
         "x", *paths])
    with open(csv_path) as f:
        return {float(r["fov_deg"]): (float(r["median_log_rmse"]), float(r["condition_worst"]))
                for r in csv.DictReader(f)}


def evaluate(acq, basis, directions, paths, a, csv_path):
    res = run([acq, "basis", "eval", "--basis", basis, "--directions", directions, "--k",
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
    ap.add_argument("--optimise", action="store_true",
                    help="also directions optimised for each fold's basis (--n of them)")
    ap.add_argument("--n", type=int, default=20)
    ap.add_argument("--fov-deg", help="also score over these fields of view, e.g. 0,4,10")
    ap.add_argument("--out", help="default out/study/basis_cv_k{K}_eta{ETA}[_opt]")
    a = ap.parse_args()
    if not a.out:
        a.out = os.path.join(ROOT, "out", "study",
                             f"basis_cv_k{a.k}_eta{a.eta:g}" + ("_opt" if a.optimise else ""))
    acq = os.path.join(a.build, "src", "cli", "acq")
    os.makedirs(a.out, exist_ok=True)
    all_materials = materials()
    fold_of = {}
    for source in SOURCES:
        names = [m for m in all_materials if m[0] == source]
        for i, m in enumerate(names):
            fold_of[m] = i % a.folds
    rows, fov_rows = [], []
    for fold in range(a.folds):
        test = [m for m in all_materials if fold_of[m] == fold]
        test_paths = [m[2] for m in test]
        train_all = [m[2] for m in all_materials if fold_of[m] != fold]
        train_merl = [m[2] for m in all_materials if fold_of[m] != fold and m[0] == "merl"]
        for basis_name, train in (("merl+rgl", train_all), ("merl", train_merl)):
            stem = os.path.join(a.out, f"fold{fold}_{basis_name}")
            basis = stem + ".acqb"
            build(acq, train, basis)
            sets = [("given", a.directions)]
            if a.optimise:
                optimise(acq, basis, a, stem + "_optimised.tsv")
                sets.append(("optimised", stem + "_optimised.tsv"))
            for set_name, directions in sets:
                scores = evaluate(acq, basis, directions, test_paths, a,
                                  f"{stem}_{set_name}.csv")
                for source, name, _ in test:
                    rows.append({"basis": basis_name, "directions": set_name, "fold": fold,
                                 "source": source, "name": name,
                                 "family": family(source, name), "channels": scores[name]})
                if a.fov_deg:
                    fov = evaluate_fov(acq, basis, directions, test_paths, a,
                                       f"{stem}_{set_name}_fov.csv")
                    for deg, (med, cond) in fov.items():
                        fov_rows.append({"basis": basis_name, "directions": set_name,
                                         "fold": fold, "fov_deg": deg, "median": med,
                                         "condition_worst": cond})
            os.remove(basis)  # 300-400 MB each
        print(f"fold {fold + 1} of {a.folds}: {len(test)} materials scored", flush=True)

    with open(os.path.join(a.out, "per_material.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["basis", "directions", "fold", "source", "family", "material", "log_rmse_R",
                    "log_rmse_G", "log_rmse_B"])
        for r in rows:
            w.writerow([r["basis"], r["directions"], r["fold"], r["source"], r["family"], r["name"],
                        *[f"{c:.5f}" for c in r["channels"]]])
    text = [f"k-fold cross-validation ({a.folds} folds), directions: given = {a.directions}"
            + (f", optimised = {a.n} optimised for each fold's basis" if a.optimise else "")
            + f"; k = {a.k}, eta = {a.eta}; log-space RMSE of materials no basis trained on",
            "columns: materials, median over their channels, mean over materials, worst material"]
    for title, key in (("overall", lambda r: (r["directions"], r["basis"])),
                       ("per source", lambda r: (r["directions"], r["basis"], r["source"])),
                       ("per family", lambda r: (r["directions"], r["family"], r["basis"]))):
        text.append(f"\n{title}:")
        for g, n, med, mean, worst, worst_name in summarise(rows, key):
            label = " / ".join(g) if isinstance(g, tuple) else g
            text.append(f"  {label:<44} {n:4d} {med:7.4f} {mean:7.4f} {worst:7.4f} ({worst_name})")
    if fov_rows:
        with open(os.path.join(a.out, "fov.csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(fov_rows[0]))
            w.writeheader()
            w.writerows(fov_rows)
        text.append("\nover the field of view (each position its own rows): mean over folds of "
                    "the fold's median log-space RMSE; worst condition number over folds")
        groups = {}
        for r in fov_rows:
            groups.setdefault((r["directions"], r["basis"], r["fov_deg"]), []).append(r)
        for (d, b, deg), rs in sorted(groups.items()):
            text.append(f"  {d} / {b:<9} fov {deg:4.1f} deg  "
                        f"{statistics.mean(r['median'] for r in rs):7.4f}  "
                        f"cond worst {max(r['condition_worst'] for r in rs):9.3g}")
    open(os.path.join(a.out, "summary.txt"), "w").write("\n".join(text) + "\n")
    print("\n".join(text))
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fams = sorted({r["family"] for r in rows})
        fig, ax = plt.subplots(figsize=(10, 0.32 * len(fams) + 1.5))
        series = [(d, b) for d in sorted({r["directions"] for r in rows})
                  for b in ("merl", "merl+rgl")]
        height = 0.8 / len(series)
        for j, (d, b) in enumerate(series):
            med = []
            for fam in fams:
                ch = [c for r in rows if r["family"] == fam and r["basis"] == b
                      and r["directions"] == d for c in r["channels"]]
                med.append(statistics.median(ch))
            ax.barh([i + height * j for i in range(len(fams))], med, height=height,
                    label=f"{b} basis, {d} directions")
        ax.set_yticks([i + 0.4 - height / 2 for i in range(len(fams))], fams)
        ax.set_xlabel("median log-space RMSE over the family's channels (cross-validated)")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "by_family.png"), dpi=100)
    except ImportError:
        print("(matplotlib missing: no chart)")


if __name__ == "__main__":
    main()
