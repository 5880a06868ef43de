#!/usr/bin/env bash
# Set up, build and run the main job: the README's first command.
# Until the capture pipeline exists, the main job is the basis study of issue 2: build the
# BRDF basis from 90 materials, hold out the other 10 (every tenth by sorted name from the
# sixth), and reconstruct them from the seed paper's 20 directions and from 20 random ones.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
[ -d build ] || meson setup build
ninja -C build
acq=build/src/cli/acq
out=out/main
mkdir -p "$out"
$acq basis build data/nbrdf/merl --holdout-every 10 --holdout-offset 5 -o "$out/basis90.acqb"
$acq directions random --n 20 --seed 1 -o "$out/random20.tsv"
echo
echo "== seed paper's 20 directions, k = 20, eta = 40 =="
$acq basis eval --basis "$out/basis90.acqb" --directions data/directions/seed_directions_20.tsv \
  --k 20 --eta 40 --csv "$out/eval_seed20.csv" --write-recon "$out/recon_seed20" data/nbrdf/merl
echo
echo "== 20 random directions (seed 1), k = 20, eta = 40 =="
$acq basis eval --basis "$out/basis90.acqb" --directions "$out/random20.tsv" \
  --k 20 --eta 40 --csv "$out/eval_random20.csv" data/nbrdf/merl
echo
echo "outputs in $out:"
echo "  basis90.acqb             the basis (docs/basis-format.md)"
echo "  eval_seed20.csv          per-material, per-channel errors, seed directions"
echo "  eval_random20.csv        the same for 20 random directions"
echo "  recon_seed20/*.binary    reconstructed held-out BRDFs as MERL .binary (pbrt, Mitsuba)"
