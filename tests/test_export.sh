#!/usr/bin/env bash
# The renderer exports end to end (issue 20, docs/export.md): a small synthetic card's map
# exported as glTF + MaterialX (checked by the Khronos validator and MaterialX's own
# validation) and as a Mitsuba 3 scene whose render with our BSDF plugin must equal
# `acq render view` at the same light and camera; then bad inputs, each a clear error.
# usage: test_export.sh ACQ DATA_DIR SOURCE_ROOT
set -u
acq=$1
data=$2
root=$3
python=$root/.venv/bin/python
validator=$root/tools/node/node_modules/gltf-validator
if [ ! -x "$python" ] || [ ! -d "$validator" ]; then
  echo "the export tools are not set up (.venv, tools/node): run tools/setup.sh"
  # CI (tools/run-tests.sh) requires them; a bare `meson test` without set-up skips.
  [ "${ACQ_REQUIRE_EXPORT_TOOLS:-0}" = 1 ] && exit 1
  exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
passed=0
check() {  # name, command...: exit 0 expected
  local name=$1; shift
  local out
  if out=$("$@" 2>&1); then
    passed=$((passed + 1)); echo "ok: $name"; [ -n "$out" ] && echo "$out" | tail -3 | sed 's/^/    /'
  else
    failures=$((failures + 1)); echo "FAIL: $name"; echo "$out" | tail -15
  fi
}
expect_error() {  # name, expected substring, -- command...: exit 1 with the substring
  local name=$1 pattern=$2; shift 3
  local out rc
  out=$("$@" 2>&1); rc=$?
  if [ "$rc" -eq 1 ] && grep -qF -- "$pattern" <<<"$out"; then
    passed=$((passed + 1)); echo "ok: $name"
  else
    failures=$((failures + 1)); echo "FAIL: $name (exit $rc, wanted 1 and: $pattern)"; echo "$out" | tail -5
  fi
}

# A basis of six materials (8 components: seconds to build) and a 40 x 40 card of three of
# them at a 4 degree field of view, each row lookup.
mats=""
for m in white-paint brass black-fabric pink-jasper red-phenolic alum-bronze; do mats="$mats $data/nbrdf/merl/$m.h5"; done
# shellcheck disable=SC2086
"$acq" basis build $mats -o "$tmp/b.acqb" --components 8 --quiet >/dev/null || { echo "FAIL: basis"; exit 1; }
for lookup in nearest interpolated; do
  "$acq" reconstruct synthetic --basis "$tmp/b.acqb" --directions "$data/directions/seed_directions_20.tsv" \
    --materials-dir "$data/nbrdf/merl" --materials white-paint,brass,black-fabric --size 40x40 --k 8 \
    --fov-deg 4 --lookup $lookup --quiet -o "$tmp/$lookup.exr" >/dev/null \
    || { echo "FAIL: reconstruction ($lookup)"; exit 1; }
done

check "export pbr" "$acq" export pbr --map "$tmp/nearest.exr" -o "$tmp/pbr" --quiet
check "export pbr --model schlick" "$acq" export pbr --map "$tmp/nearest.exr" -o "$tmp/pbr-schlick" --model schlick --quiet
check "glTF passes the Khronos validator with no errors" \
  node "$root/tests/gltf_validate.js" "$validator" "$tmp/pbr/material.gltf"
check "MaterialX document passes MaterialX's validation; fit error map finite" \
  "$python" "$root/tests/export_checks.py" pbr "$tmp/pbr"
# The model's layers in both documents: F90 as glTF's specularTexture and standard_surface's
# specular; a coat (brass and white paint take one) as KHR_materials_clearcoat and the coat.
# The model without them (schlick) writes neither coat.png nor the extension, F90 1 everywhere.
check "F90 and the coat reach the glTF and the MaterialX document; schlick writes neither" \
  "$python" -c "import json
fit = json.load(open('$tmp/pbr/fit.json')); assert fit['model'] == 'coated' and fit['coated_pixels'] > 0, fit
g = json.load(open('$tmp/pbr/material.gltf')); e = g['materials'][0]['extensions']
uri = lambda t: g['images'][g['textures'][t['index']]['source']]['uri']
assert uri(e['KHR_materials_specular']['specularTexture']) == 'specular_weight.png', e
c = e['KHR_materials_clearcoat']; assert uri(c['clearcoatTexture']) == uri(c['clearcoatRoughnessTexture']) == 'coat.png', c
assert 'KHR_materials_clearcoat' in g['extensionsUsed']
m = open('$tmp/pbr/material.mtlx').read(); assert 'coat.png' in m and 'specular_weight.png' in m
import os; g2 = json.load(open('$tmp/pbr-schlick/material.gltf'))
assert 'KHR_materials_clearcoat' not in g2['extensionsUsed'] and not os.path.exists('$tmp/pbr-schlick/coat.png')
assert json.load(open('$tmp/pbr-schlick/fit.json'))['coated_pixels'] == 0
import mitsuba as mi, numpy as np; mi.set_variant('scalar_rgb')
w = np.array(mi.Bitmap('$tmp/pbr-schlick/specular_weight.png')); assert w.shape[2] == 4 and (w == 255).all(), w.shape"

# A map with estimated normals (an embossed card): normal.png, the glTF's normalTexture with
# the quad's tangents, the MaterialX normal map; both still valid.
"$acq" reconstruct synthetic --basis "$tmp/b.acqb" --directions "$data/directions/seed_directions_20.tsv" \
  --materials-dir "$data/nbrdf/merl" --materials white-paint,brass,black-fabric --size 40x40 --k 8 \
  --fov-deg 4 --relief-deg 10 --normals --quiet -o "$tmp/normals.exr" >/dev/null \
  || { echo "FAIL: reconstruction with normals"; exit 1; }
check "export pbr of a map with normals" "$acq" export pbr --map "$tmp/normals.exr" -o "$tmp/pbr-normals" --quiet
check "its normal map is written and referenced by the glTF and the MaterialX document" \
  "$python" -c "import json, sys; g = json.load(open('$tmp/pbr-normals/material.gltf'));
t = g['materials'][0]['normalTexture']['index']; assert g['images'][t]['uri'] == 'normal.png', g['images']
assert 'TANGENT' in g['meshes'][0]['primitives'][0]['attributes']
assert 'normal.png' in open('$tmp/pbr-normals/material.mtlx').read()
assert 'normalTexture' not in json.load(open('$tmp/pbr/material.gltf'))['materials'][0]"
check "the glTF with a normal map passes the Khronos validator with no errors" \
  node "$root/tests/gltf_validate.js" "$validator" "$tmp/pbr-normals/material.gltf"
check "the MaterialX document with a normal map passes MaterialX's validation" \
  "$python" "$root/tests/export_checks.py" pbr "$tmp/pbr-normals"

# Mitsuba: our plugin's render against our renderer, both lookups and two light poses. The
# point light makes the render deterministic but for where each sample falls in its pixel
# (4 spp, a box filter: the directions move by under a pixel's angle, 0.3 mrad).
for lookup in nearest interpolated; do
  for pose in "30 0" "55 140"; do
    set -- $pose
    out=$tmp/mitsuba-$lookup-$1
    check "export mitsuba ($lookup, light at $1/$2 deg)" \
      "$acq" export mitsuba --map "$tmp/$lookup.exr" -o "$out" --light-theta-deg "$1" --light-phi-deg "$2"
    "$acq" render view --map "$tmp/$lookup.exr" -o "$out/ours.exr" --light-theta-deg "$1" --light-phi-deg "$2" >/dev/null
    check "Mitsuba render equals acq render view within 2% ($lookup, light at $1/$2 deg)" \
      "$python" "$root/tests/export_checks.py" mitsuba "$out" 0.02
  done
done

# Bad input, each refused before anything is written.
mkdir -p "$tmp/full" && touch "$tmp/full/notes.txt"
expect_error "export into a folder with other files" "not empty" -- \
  "$acq" export pbr --map "$tmp/nearest.exr" -o "$tmp/full"
expect_error "mitsuba export into a folder with other files" "not empty" -- \
  "$acq" export mitsuba --map "$tmp/nearest.exr" -o "$tmp/full"
"$acq" basis build "$data/nbrdf/merl/brass.h5" "$data/nbrdf/merl/white-paint.h5" "$data/nbrdf/merl/black-fabric.h5" -o "$tmp/other.acqb" \
  --components 8 --quiet >/dev/null
expect_error "a basis that is not the map's" "checksum differs" -- \
  "$acq" export pbr --map "$tmp/nearest.exr" --basis "$tmp/other.acqb" -o "$tmp/x1"
mv "$tmp/b.acqb" "$tmp/moved.acqb"
expect_error "a map without its basis" "b.acqb" -- \
  "$acq" export mitsuba --map "$tmp/nearest.exr" -o "$tmp/x2"
mv "$tmp/moved.acqb" "$tmp/b.acqb"
expect_error "a session without validation data" "validation" -- \
  "$acq" export pbr --map "$tmp/nearest.exr" --session "$tmp/pbr" -o "$tmp/x3" --quiet
expect_error "an unknown model" "unknown model 'lambert'" -- \
  "$acq" export pbr --map "$tmp/nearest.exr" --model lambert -o "$tmp/x4" --quiet
for d in x1 x2 x3 x4; do
  if [ -e "$tmp/$d" ]; then failures=$((failures + 1)); echo "FAIL: a refused export left $d"; fi
done

echo "$passed passed, $failures failed"
[ "$failures" -eq 0 ]
