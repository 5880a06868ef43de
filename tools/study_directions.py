#!/usr/bin/python3
"""The direction study of issue 3, through the real `acq` tool. Writes CSV and PNG charts to
out/study/directions/ (or --out):

  error_vs_n.png    held-out log-space error and condition number against n, at fields of view
                    of 0, 4 and 10 degrees, for our optimised sets, the paper's condition-only
                    constrained sets, unconstrained NJR15 sets, field-of-view-aware sets, random
                    sets and the seed's published 20 (the paper's Fig. 4, extended)
  optimizer_time.png  optimiser run time against n for each variant
  stability.png     error against observation noise; table of n < k, bunched, eta = 0
  results.csv, stability.csv, timings.csv

Basis: the issue's split (90 training materials, every tenth from the sixth held out).
usage: /usr/bin/python3 tools/study_directions.py [--build build] [--out DIR] [--quick]"""
import argparse
import csv
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MATERIALS = os.path.join(ROOT, "data", "nbrdf", "merl")
SEED = os.path.join(ROOT, "data", "directions", "seed_directions_20.tsv")

# Each variant: label, extra optimiser flags.
VARIANTS = [
    ("ours (expected error, cond <= 200, camera <= 65 deg)", []),
    ("condition only, camera <= 65 deg (Yu et al.)", ["--score", "condition"]),
    ("condition only, unconstrained (NJR15)", ["--score", "condition", "--unconstrained"]),
    ("ours, field-of-view aware (10 deg, mean)",
     ["--fov-deg", "10", "--fov-objective", "mean", "--fov-grid", "5"]),
]
RANDOM_SEEDS = [1, 2, 3]
FOVS = "0,4,10"


def run(cmd):
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"study: {' '.join(cmd)} failed:\n{res.stdout}\n{res.stderr}")
    return res.stdout + res.stderr


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "study", "directions"))
    ap.add_argument("--quick", action="store_true", help="n in 5, 10, 20 only")
    ap.add_argument("--reuse", action="store_true",
                    help="keep results.csv and timings.csv from an earlier run; redo the rest")
    a = ap.parse_args()
    acq = os.path.join(a.build, "src", "cli", "acq")
    os.makedirs(os.path.join(a.out, "sets"), exist_ok=True)
    basis = os.path.join(a.out, "basis90.acqb")
    if not os.path.exists(basis):
        print("study: building the basis (90 materials, 10 held out)")
        run([acq, "basis", "build", MATERIALS, "--holdout-every", "10", "--holdout-offset", "5",
             "-o", basis, "--quiet"])
    results = os.path.join(a.out, "results.csv")
    stability = os.path.join(a.out, "stability.csv")
    timings_csv = os.path.join(a.out, "timings.csv")
    reuse = a.reuse and os.path.exists(results) and os.path.exists(timings_csv)
    for f in ((stability,) if reuse else (results, stability)):
        if os.path.exists(f):
            os.remove(f)

    def evaluate(tsv, label, csv_path=results, extra=()):
        return run([acq, "directions", "eval", "--basis", basis, "--directions", tsv,
                    "--fov-deg", FOVS, "--csv", csv_path, "--label", label, MATERIALS,
                    *extra])

    ns = [5, 10, 20] if a.quick else [5, 10, 15, 20, 25, 30, 35, 40]
    timings = []
    for n in [] if reuse else ns:
        for i, (label, flags) in enumerate(VARIANTS):
            tsv = os.path.join(a.out, "sets", f"v{i}_n{n}.tsv")
            out = run([acq, "directions", "optimize", "--basis", basis, "--n", str(n), "-o", tsv,
                       "--quiet", *flags])
            seconds = float(re.search(r"in ([\d.]+) s", out).group(1))
            timings.append((label, n, seconds))
            evaluate(tsv, label)
            print(f"study: n = {n:2d} {label}: optimised in {seconds:.1f} s")
        for s in RANDOM_SEEDS:
            tsv = os.path.join(a.out, "sets", f"random_n{n}_s{s}.tsv")
            run([acq, "directions", "random", "--n", str(n), "--seed", str(s), "-o", tsv])
            evaluate(tsv, "random")
    if reuse:
        timings = [(r["variant"], int(r["n"]), float(r["seconds"])) for r in read_csv(timings_csv)]
    else:
        evaluate(SEED, "seed paper's 20 (Yu et al. Fig. 3)")
        with open(timings_csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(["variant", "n", "seconds"])
            w.writerows(timings)

    # Stability: noise, n < k, bunched directions, eta = 0 (field of view 0).
    ours20 = os.path.join(a.out, "sets", "v0_n20.tsv")
    njr20 = os.path.join(a.out, "sets", "v2_n20.tsv")
    rnd20 = os.path.join(a.out, "sets", "random_n20_s1.tsv")
    noise = "0,0.01,0.03,0.1,0.3,1"
    for tsv, label in ((ours20, "ours n=20"), (SEED, "seed's 20"), (njr20, "NJR15 n=20"),
                       (rnd20, "random n=20")):
        run([acq, "directions", "eval", "--basis", basis, "--directions", tsv, "--noise", noise,
             "--csv", stability, "--label", label, MATERIALS])
    bunched = os.path.join(a.out, "sets", "bunched20.tsv")
    with open(bunched, "w") as f:
        f.write("# 20 directions bunched within 2 degrees of (theta_h 20, theta_d 30, phi_d 90)\n")
        f.write("theta_h\ttheta_d\tphi_d\n")
        for i in range(20):
            f.write(f"{20 + 0.1 * i:.3f}\t{30 + 0.1 * (i % 5):.3f}\t{90 + 0.5 * (i // 5):.3f}\n")
    cases = [
        (ours20, "ours n=20, eta=40", ["--eta", "40"]),
        (ours20, "ours n=20, eta=0", ["--eta", "0"]),
        (rnd20, "random n=20, eta=0", ["--eta", "0"]),
        (os.path.join(a.out, "sets", "v0_n10.tsv"), "ours n=10 with k=20 (n < k)", ["--k", "20"]),
        (bunched, "bunched n=20", []),
    ]
    warnings = {}
    for tsv, label, flags in cases:
        out = run([acq, "directions", "eval", "--basis", basis, "--directions", tsv, "--noise",
                   "0,0.1", "--csv", stability, "--label", label, MATERIALS, *flags])
        warnings[label] = "warning" in out

    charts(a.out, read_csv(results), read_csv(stability), timings, warnings)


def charts(out, rows, stab, timings, warnings):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fovs = sorted({float(r["fov_deg"]) for r in rows})
    labels = [v[0] for v in VARIANTS]
    colours = ["tab:blue", "tab:orange", "tab:green", "tab:purple"]
    fig, axes = plt.subplots(2, len(fovs), figsize=(5 * len(fovs), 8), sharex=True)
    for col, fov in enumerate(fovs):
        at = [r for r in rows if abs(float(r["fov_deg"]) - fov) < 0.01]
        for label, colour in zip(labels, colours):
            pts = sorted((int(r["n"]), float(r["median_log_rmse"]), float(r["condition_median"]))
                         for r in at if r["label"] == label)
            if pts:
                axes[0, col].plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=colour,
                                  label=label)
                axes[1, col].semilogy([p[0] for p in pts], [p[2] for p in pts], "o-",
                                      color=colour, label=label)
        rnd = {}
        for r in at:
            if r["label"] == "random":
                rnd.setdefault(int(r["n"]), []).append(
                    (float(r["median_log_rmse"]), float(r["condition_median"])))
        ns = sorted(rnd)
        for row, idx in ((0, 0), (1, 1)):
            mean = [sum(v[idx] for v in rnd[n]) / len(rnd[n]) for n in ns]
            lo = [min(v[idx] for v in rnd[n]) for n in ns]
            hi = [max(v[idx] for v in rnd[n]) for n in ns]
            axes[row, col].plot(ns, mean, "s--", color="tab:gray", label="random (mean of 3)")
            axes[row, col].fill_between(ns, lo, hi, color="tab:gray", alpha=0.2)
        for r in at:
            if r["label"].startswith("seed"):
                axes[0, col].plot(20, float(r["median_log_rmse"]), "k*", ms=14, label=r["label"])
                axes[1, col].semilogy(20, float(r["condition_median"]), "k*", ms=14,
                                      label=r["label"])
        axes[0, col].set_title(f"field of view {fov:g} deg" +
                               (" (centre only)" if fov == 0 else ", 10 x 10 positions"))
        axes[0, col].set_ylabel("median held-out log-space RMSE")
        axes[0, col].set_ylim(0, 1.2)
        axes[1, col].set_ylabel("median condition number over positions")
        axes[1, col].set_xlabel("number of directions n (k = n)")
        axes[0, col].grid(alpha=0.3)
        axes[1, col].grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7, loc="upper right")
    fig.suptitle("Held-out reconstruction (10 MERL materials, basis from 90), eta = 40, "
                 "camera and light at 1000 mm")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "error_vs_n.png"), dpi=90)

    fig, ax = plt.subplots(figsize=(6, 4))
    for label, colour in zip(labels, colours):
        pts = sorted((n, s) for l, n, s in timings if l == label)
        ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=colour, label=label)
    ax.set_xlabel("number of directions n")
    ax.set_ylabel("optimiser wall time (s), 2 cores")
    ax.set_title("Direction optimiser run time (1000 candidates per step)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "optimizer_time.png"), dpi=90)

    fig, (ax, tab) = plt.subplots(1, 2, figsize=(12, 4.5), gridspec_kw={"width_ratios": [1, 1.2]})
    for label in ("ours n=20", "seed's 20", "NJR15 n=20", "random n=20"):
        pts = sorted((float(r["noise_sigma"]), float(r["median_log_rmse"]))
                     for r in stab if r["label"] == label)
        ax.plot([max(p[0], 0.003) for p in pts], [p[1] for p in pts], "o-", label=label)
    ax.set_xscale("log")
    ax.set_xlabel("observation noise sigma (log space ~ relative; 0 plotted at 0.003)")
    ax.set_ylabel("median held-out log-space RMSE")
    ax.set_title("Error against noise, field of view 0")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    cells = []
    for label in ("ours n=20, eta=40", "ours n=20, eta=0", "random n=20, eta=0",
                  "ours n=10 with k=20 (n < k)", "bunched n=20"):
        r0 = [r for r in stab if r["label"] == label and float(r["noise_sigma"]) == 0][0]
        r1 = [r for r in stab if r["label"] == label and float(r["noise_sigma"]) == 0.1][0]
        cells.append([label, f"{float(r0['condition_centre']):.3g}", f"{float(r0['noise_gain']):.2f}",
                      f"{float(r0['median_log_rmse']):.3f}", f"{float(r1['median_log_rmse']):.3f}",
                      "yes" if warnings.get(label) else "no"])
    tab.axis("off")
    t = tab.table(cellText=cells, colLabels=["case", "condition", "noise gain", "error",
                                              "error, noise 0.1", "tool warns"], loc="center",
                  colWidths=[0.34, 0.12, 0.12, 0.1, 0.16, 0.12])
    t.auto_set_font_size(False)
    t.set_fontsize(8)
    t.scale(1, 1.6)
    tab.set_title("Where the method fails (field of view 0)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "stability.png"), dpi=90)
    print(f"study: wrote {out}/error_vs_n.png, optimizer_time.png, stability.png and CSVs")


if __name__ == "__main__":
    main()
