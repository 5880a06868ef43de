#!/usr/bin/env bash
# The renderer exports' tools (docs/export.md), beside the Debian packages tools/setup.sh
# installs: .venv (Debian's python3 -m venv) with Mitsuba 3, Dr.Jit, MaterialX and numpy at the
# versions tools/requirements-renderers.txt pins, and tools/node/node_modules with the Khronos
# glTF validator and puppeteer-core (the live view's browser test drives Debian's Chromium). Idempotent: each is skipped when it is there at the pinned versions.
set -euo pipefail
cd "$(dirname "$0")/.."
requirements=tools/requirements-renderers.txt
stamp=.venv/.acq-requirements
if [ -x .venv/bin/python ] && cmp -s "$requirements" "$stamp"; then
  echo "setup: .venv up to date"
else
  echo "setup: creating .venv with $(grep -v '^#' "$requirements" | tr '\n' ' ')"
  /usr/bin/python3 -m venv .venv
  .venv/bin/pip install --quiet --disable-pip-version-check -r "$requirements"
  cp "$requirements" "$stamp"
fi
node_stamp=tools/node/node_modules/.acq-package
if [ -d tools/node/node_modules/gltf-validator ] && cmp -s tools/node/package.json "$node_stamp"; then
  echo "setup: tools/node up to date"
else
  echo "setup: installing the glTF validator and puppeteer-core into tools/node"
  (cd tools/node && npm install --silent --no-audit --no-fund --no-package-lock)
  cp tools/node/package.json "$node_stamp"
fi
