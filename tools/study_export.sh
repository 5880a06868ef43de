#!/usr/bin/env bash
# The renderer exports measured (issue 20; docs/export.md): on the main job's simulated colour
# session (tools/run-main.sh makes out/sessions/sim-card), reprocessed from its reconstruction
# so that its validation views' data are kept,
#   1. the Mitsuba plugin's render against `acq render view` at 1, 4 and 16 samples per pixel,
#      and two renders at 4 spp with different seeds against each other (the Monte Carlo noise);
#   2. the analytic fit's price, per model (schlick, weighted, coated at the default zenith limit,
#      coated at 80 degrees): its error per true material, the validation views with the fitted
#      maps against the measured map, its time; a chart (fit_price.png);
#   3. the fitted maps in Mitsuba's principled BSDF against our evaluation of the same maps: the
#      schlick model's, the one it holds (no F90, no GGX coat);
#   4. side-by-side pictures for the README (docs/images/export_*.png);
#   5. the glTF imported into Blender and rendered with Cycles at the same light and camera, its
#      light's units scaled onto Mitsuba's principled render of the same maps (if installed), also
#      with the light from the side and its mirror image (the export's orientation);
#   6. the MaterialX document rendered by MaterialX's own GLSL renderer (what MaterialXView draws
#      with) at the same light and camera, scaled the same way (if xvfb-run is installed), at the
#      light of step 1 and at one from the side (45/90 degrees: the picture's orientation);
#   7. the time to fit a 1-megapixel map (a 1024 x 1024 synthetic card).
# usage: tools/study_export.sh [OUT]   (default out/study/export)
set -euo pipefail
cd "$(dirname "$0")/.."
acq=build/src/cli/acq
py=.venv/bin/python
out=${1:-out/study/export}
session=out/sessions/sim-card
[ -f "$session/report.json" ] || { echo "run tools/run-main.sh first (it makes $session)"; exit 1; }
rm -rf "$out" && mkdir -p "$out"
$acq session process "$session" --from reconstruction -o "$out/session" > "$out/session.log"
map=$out/session/svbrdf.exr

echo "== 1. Mitsuba with the plugin against acq render view (light 30/0, camera overhead) =="
$acq export mitsuba --map "$map" -o "$out/mitsuba" > /dev/null
$acq render view --map "$map" -o "$out/ours.exr" > /dev/null
for spp in 1 4 16; do
  $py "$out/mitsuba/render.py" --spp $spp -o "$out/mitsuba_${spp}spp.exr"
  echo "  $spp spp: relative RMS $($py tools/chart_export.py compare "$out/mitsuba_${spp}spp.exr" "$out/ours.exr")"
done

echo "== 2. the analytic fit's price =="
$acq export pbr --map "$map" --session "$out/session" -o "$out/pbr" --quiet | tee "$out/pbr.txt"
for model in schlick weighted; do
  echo "-- --model $model"
  $acq export pbr --map "$map" --session "$out/session" -o "$out/pbr_$model" --model $model --quiet
done
echo "-- --max-zenith-deg 80"
$acq export pbr --map "$map" --session "$out/session" -o "$out/pbr_80" --max-zenith-deg 80 --quiet
$py tools/chart_export.py fit "$out/pbr_schlick/fit.json" "$out/pbr_weighted/fit.json" \
  "$out/pbr_80/fit.json" "$out/pbr/fit.json" "$out/fit_price.png"

echo "== 3. the fitted maps in Mitsuba's principled BSDF (the schlick model: the one it holds) =="
$py "$out/mitsuba/render.py" --spp 16 --fitted "$out/pbr_schlick" -o "$out/principled.exr"
echo "  principled (fitted maps) against acq render view of the measured map: relative RMS" \
  "$($py tools/chart_export.py compare "$out/principled.exr" "$out/ours.exr")"

# The light from the side (45/90 degrees): a mirror image of the quad or of the light in another
# renderer shows against this render (steps 5 and 6).
$py - "$out/mitsuba/scene.json" "$out/side.json" << 'PY'
import json, sys
d = json.load(open(sys.argv[1])); d["light"].update(theta_deg=45.0, phi_deg=90.0)
json.dump(d, open(sys.argv[2], "w"))
PY
$py "$out/mitsuba/render.py" --spp 16 --fitted "$out/pbr_schlick" --description "$out/side.json" \
  -o "$out/principled_side.exr" > /dev/null

echo "== 4. pictures =="
mkdir -p docs/images
$py tools/chart_export.py side "$out/ours.exr" "$out/mitsuba_16spp.exr" "$out/principled.exr" \
  docs/images/export_renders.png
cp "$out/fit_price.png" docs/images/export_fit_price.png

# Blender 3.4's Principled BSDF (Debian 12) has no F90 and a GTR1 clearcoat: like Mitsuba's
# principled it is compared on the schlick model's export.
echo "== 5. the glTF in Blender (Cycles), when Blender is installed (tools/setup.sh --viewers) =="
if command -v blender > /dev/null; then
  blender -b --factory-startup -P tools/render_blender.py -- "$out/pbr_schlick/material.gltf" \
    "$out/blender_raw.exr" --spp 64 > "$out/blender.log" 2>&1 || { tail "$out/blender.log"; exit 1; }
  echo "  Blender against Mitsuba's principled BSDF, both the fitted maps: $($py tools/chart_export.py \
    scaled "$out/blender_raw.exr" "$out/principled.exr" "$out/blender.exr")"
  blender -b --factory-startup -P tools/render_blender.py -- "$out/pbr_schlick/material.gltf" \
    "$out/blender_seed1.exr" --spp 64 --seed 1 > /dev/null 2>&1
  echo "  Cycles' noise, two seeds at 64 spp: relative RMS" \
    "$($py tools/chart_export.py compare "$out/blender_seed1.exr" "$out/blender_raw.exr")"
  echo "  Blender against acq render view of the measured map: relative RMS" \
    "$($py tools/chart_export.py compare "$out/blender.exr" "$out/ours.exr")"
  $py tools/chart_export.py side "$out/ours.exr" "$out/principled.exr" "$out/blender.exr" \
    docs/images/export_blender.png
  for phi in 90 270; do
    blender -b --factory-startup -P tools/render_blender.py -- "$out/pbr_schlick/material.gltf" \
      "$out/blender_${phi}_raw.exr" --spp 64 --light-theta-deg 45 --light-phi-deg $phi > /dev/null 2>&1
    echo "  light at 45/$phi, Blender against Mitsuba's principled at 45/90 (270: mirrored, should be" \
      "worse): $($py tools/chart_export.py scaled "$out/blender_${phi}_raw.exr" "$out/principled_side.exr" \
      "$out/blender_$phi.exr")"
  done
else
  echo "  skipped: no blender on PATH"
fi

echo "== 6. the MaterialX document in MaterialX's GLSL renderer, when xvfb-run is installed (tools/setup.sh --viewers) =="
if command -v xvfb-run > /dev/null; then
  xvfb-run -a $py tools/render_materialx.py "$out/pbr_schlick" "$out/materialx_raw.exr" > /dev/null
  echo "  MaterialX against Mitsuba's principled BSDF, both the schlick model's maps: $($py tools/chart_export.py \
    scaled "$out/materialx_raw.exr" "$out/principled.exr" "$out/materialx.exr")"
  # The default model's export (F90 and the coat, which standard_surface holds), scaled onto our
  # render of the measured map: how near a real renderer of the fitted maps comes to the data.
  xvfb-run -a $py tools/render_materialx.py "$out/pbr" "$out/materialx_default_raw.exr" > /dev/null
  echo "  MaterialX, the default model's maps, against acq render view of the measured map:" \
    "$($py tools/chart_export.py scaled "$out/materialx_default_raw.exr" "$out/ours.exr" \
    "$out/materialx_default.exr")"
  echo "  the same for the schlick model's maps:" \
    "$($py tools/chart_export.py scaled "$out/materialx_raw.exr" "$out/ours.exr" \
    "$out/materialx_schlick_scaled.exr")"
  echo "  MaterialX against acq render view of the measured map: relative RMS" \
    "$($py tools/chart_export.py compare "$out/materialx.exr" "$out/ours.exr")"
  $py tools/chart_export.py side "$out/ours.exr" "$out/principled.exr" "$out/materialx.exr" "$out/materialx_default.exr" \
    docs/images/export_materialx.png
  xvfb-run -a $py tools/render_materialx.py "$out/pbr_schlick" "$out/materialx_side_raw.exr" \
    --light-theta-deg 45 --light-phi-deg 90 > /dev/null
  echo "  light at 45/90, MaterialX against Mitsuba's principled: $($py tools/chart_export.py \
    scaled "$out/materialx_side_raw.exr" "$out/principled_side.exr" "$out/materialx_side.exr")"
  xvfb-run -a $py tools/render_materialx.py "$out/pbr_schlick" "$out/materialx_mirror_raw.exr" \
    --light-theta-deg 45 --light-phi-deg 270 > /dev/null
  echo "  the same with the light mirrored (45/270; should be worse): $($py tools/chart_export.py \
    scaled "$out/materialx_mirror_raw.exr" "$out/principled_side.exr" "$out/materialx_mirror.exr")"
else
  echo "  skipped: no xvfb-run on PATH"
fi

echo "== 7. the time to fit a 1-megapixel map =="
$acq reconstruct synthetic --basis out/main/basis116.acqb --directions data/directions/seed_directions_20.tsv \
  --size 1024x1024 --fov-deg 4 --method independent -o "$out/card1024.exr" --quiet > /dev/null
/usr/bin/time -f "  peak memory %M KB" $acq export pbr --map "$out/card1024.exr" -o "$out/pbr1024" --quiet
echo "-- --model schlick"
$acq export pbr --map "$out/card1024.exr" -o "$out/pbr1024_schlick" --model schlick --quiet
