#!/usr/bin/env bash
# One command for a newcomer: install dependencies, build, and render a real scene (the Khronos WaterBottle,
# ../shared/assets/gltf/WaterBottle) through the WC18 pipeline to out/waterbottle_wc18.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
mkdir -p out
./build/app/aquarelle render scenes/data/waterbottle.json --style wc18 \
  --out out/waterbottle_wc18.png --targets out/waterbottle_targets
echo "quickstart: wrote out/waterbottle_wc18.png (G-buffer and intermediates as EXR in out/waterbottle_targets/)"
