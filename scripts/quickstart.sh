#!/usr/bin/env bash
# One command for a newcomer: install dependencies, build, and render a real scene (Suzanne,
# ../shared/assets) through the WC18 watercolor pipeline to out/suzanne_wc18.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
mkdir -p out
./build/app/aquarelle render scenes/data/suzanne.json --style wc18 --width 1280 --height 720 \
  --out out/suzanne_wc18.png --targets out/suzanne_targets
echo "quickstart: wrote out/suzanne_wc18.png (G-buffer and intermediates as EXR in out/suzanne_targets/)"
