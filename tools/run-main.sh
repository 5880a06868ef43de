#!/usr/bin/env bash
# Set up, build and run the main job: the README's first command.
# The offline chain on simulated data, then a whole simulated session through acqd:
#   1. the BRDF bases: the product's default from 90 MERL and the 26 RGL-EPFL materials, and the
#      paper's setting from the 90 MERL materials alone, the other 10 MERL held out from both
#      (every tenth by sorted name from the sixth); each evaluated with the seed paper's 20
#      directions, the MERL-only one also with 20 random ones;
#   2. 20 directions optimised for this basis under the gantry's constraints, evaluated likewise
#      at the sample's centre and over 4 and 10 degree fields of view;
#   3. a synthetic printed card of four held-out materials, observed per pixel at a 4 degree
#      field of view through the optimised directions, reconstructed pixel by pixel into an
#      SVBRDF map and scored against its ground truth;
#   4. renders of the map: quick looks, a view under a new arm pose, spheres of chosen pixels;
#   5. acqd on examples/plan-sim.yaml: the simulated instrument's colour camera captures the
#      calibration boards, the card, the Spectralon and a colour chart, and acqd calibrates,
#      fits the colour matrix, aligns and reconstructs it into a colour SVBRDF map;
#   6. acqd replays that session (examples/plan-replay.yaml) through the same code;
#   7. the session's map exported: Lambert + GGX fitted per pixel as glTF and MaterialX, and the
#      measured map as a Mitsuba 3 scene, rendered by Mitsuba.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
[ -d build ] || meson setup build
ninja -C build
acq=build/src/cli/acq
out=out/main
mkdir -p "$out"
# The issue-2 split: every tenth MERL material by sorted name from the sixth (what
# --holdout-every 10 --holdout-offset 5 holds out of MERL alone), named so that both bases hold
# out the same ten.
split=black-fabric,brass,dark-specular-fabric,green-fabric,natural-209,pink-jasper,red-phenolic
split=$split,specular-green-phenolic,tungsten-carbide,white-paint
$acq basis build data/nbrdf/merl data/nbrdf/rgl --holdout "$split" -o "$out/basis116.acqb"
$acq basis build data/nbrdf/merl --holdout "$split" -o "$out/basis90.acqb"
$acq directions random --n 20 --seed 1 -o "$out/random20.tsv"
echo
echo "== 1. the default basis (MERL + RGL), seed paper's 20 directions, the default k and eta =="
$acq basis eval --basis "$out/basis116.acqb" --directions data/directions/seed_directions_20.tsv \
  --csv "$out/eval_seed20_default.csv" data/nbrdf/merl
echo
echo "== 1. the MERL-only basis (the paper's setting), seed paper's 20 directions, k = 20, eta = 40 =="
$acq basis eval --basis "$out/basis90.acqb" --directions data/directions/seed_directions_20.tsv \
  --k 20 --eta 40 --csv "$out/eval_seed20.csv" --write-recon "$out/recon_seed20" data/nbrdf/merl
echo
echo "== 1. the MERL-only basis, 20 random directions (seed 1), k = 20, eta = 40 =="
$acq basis eval --basis "$out/basis90.acqb" --directions "$out/random20.tsv" \
  --k 20 --eta 40 --csv "$out/eval_random20.csv" data/nbrdf/merl
echo
echo "== 2. 20 optimised directions (camera zenith <= 65 deg) =="
$acq directions optimize --basis "$out/basis116.acqb" --n 20 -o "$out/optimized20.tsv" --quiet
for set in data/directions/seed_directions_20.tsv "$out/optimized20.tsv"; do
  $acq directions eval --basis "$out/basis116.acqb" --directions "$set" --fov-deg 0,4,10 data/nbrdf/merl
done
echo
echo "== 2. the gantry's visiting order for the optimised directions =="
$acq directions plan --directions "$out/optimized20.tsv" -o "$out/visiting_order.tsv"
echo
echo "== 3. synthetic card, 256 x 256 pixels, 4 degree field of view, per-pixel reconstruction =="
$acq reconstruct synthetic --basis "$out/basis116.acqb" --directions "$out/optimized20.tsv" \
  --size 256x256 --fov-deg 4 -o "$out/card_svbrdf.exr" --score --quiet
echo
echo "== 4. renders =="
$acq render quicklook --map "$out/card_svbrdf.exr" -o "$out/quicklook"
$acq render view --map "$out/card_svbrdf.exr" --light-theta-deg 40 --light-phi-deg 30 \
  --camera-theta-deg 25 --camera-phi-deg 200 --fov-deg 4 -o "$out/card_view.png"
$acq render spheres --map "$out/card_svbrdf.exr" --pixel 128,20 --pixel 60,60 --pixel 200,170 \
  --pixel 40,160 -o "$out/card_spheres.png"
$acq render export --map "$out/card_svbrdf.exr" --pixel 60,60 -o "$out/card_pixel_60_60.binary"
echo
echo "== 5. a simulated colour capture through acqd (gantry on emulated USB, Bayer camera on loopback GigE) =="
rm -rf out/sessions/sim-card
build/src/daemon/acqd --session examples/plan-sim.yaml --dry-run | tail -14
build/src/daemon/acqd --session examples/plan-sim.yaml --socket "out/acqd.sock"
echo
echo "== 6. the recorded session replayed through acqd =="
rm -rf out/sessions/sim-card-replayed
build/src/daemon/acqd --session examples/plan-replay.yaml --socket "out/acqd.sock" | tail -8
echo
echo "== 7. the session's map into renderers: glTF + MaterialX fitted, Mitsuba 3 measured (docs/export.md) =="
rm -rf "$out/export"
$acq export pbr --map out/sessions/sim-card/svbrdf.exr --session out/sessions/sim-card \
  -o "$out/export/pbr" --quiet
$acq export mitsuba --map out/sessions/sim-card/svbrdf.exr -o "$out/export/mitsuba"
.venv/bin/python "$out/export/mitsuba/render.py" -o "$out/export/mitsuba/render.exr"
echo
echo "outputs in $out:"
echo "  basis116.acqb              the default basis, MERL + RGL (docs/basis-format.md)"
echo "  basis90.acqb               the MERL-only basis (the paper's setting)"
echo "  eval_seed20_default.csv    per-material, per-channel errors, default basis, seed directions"
echo "  eval_seed20.csv            the same for the MERL-only basis, k = 20, eta = 40"
echo "  eval_random20.csv          the same for 20 random directions"
echo "  recon_seed20/*.binary      reconstructed held-out BRDFs as MERL .binary (pbrt, Mitsuba)"
echo "  optimized20.tsv            optimised directions with arm angles (docs/directions.md)"
echo "  visiting_order.tsv         collision-free order and arm poses, with move times"
echo "  card_svbrdf.exr            the card's SVBRDF map (docs/svbrdf-map.md)"
echo "  quicklook/*.png            BRDF at a diffuse and a specular configuration, diagnostics"
echo "  card_view.png              the card re-rendered under a new light and camera pose"
echo "  card_spheres.png           spheres with the BRDFs of four pixels"
echo "  card_pixel_60_60.binary    one pixel's BRDF as a MERL .binary"
echo "and in out/sessions/sim-card (the simulated capture and its processing by acqd):"
echo "  frames/*.exr               every pose's frames (Bayer: boards, sample, validation, Spectralon, chart)"
echo "  catalog.sqlite             the session catalog: frames with checksums, steps, events"
echo "  calibration/               camera.cameramodel, intrinsics.txt, extrinsics.tsv, corners"
echo "  hdr/, correspondence/      merged, demosaiced camera RGB per pose; reference-to-view maps"
echo "  svbrdf.exr                 the reconstructed colour SVBRDF map, linear Rec. 709 (docs/svbrdf-map.md)"
echo "  renders/validation_*.png   the map's render beside each validation capture it never saw"
echo "  renders/validation_*.exr   each validation capture and its directions, for models made later"
echo "  report.txt, report.json    where the time went, validity, validation errors, the chart fit,"
echo "                             CIEDE2000 of the validation views, the score against the truth"
echo "  ground_truth/              the simulated card's labels, names, camera model, error.exr"
echo "and out/sessions/sim-card-replayed: the same session replayed (same frames, same map)"
echo "and in $out/export (docs/export.md):"
echo "  pbr/material.gltf, .mtlx   Lambert + GGX fitted per pixel, as glTF 2.0 and MaterialX, with"
echo "                             their textures, fit_error.exr/.png and fit.json (the fit's price)"
echo "  mitsuba/                   a Mitsuba 3 scene with the measured map's BSDF plugin;"
echo "                             render.exr rendered by it (.venv/bin/python mitsuba/render.py)"
