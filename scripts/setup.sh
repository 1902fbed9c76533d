#!/usr/bin/env bash
# Installs Aquarelle's Debian 12 dependencies (idempotent) and builds the project into build/.
# Usage: scripts/setup.sh [--no-install] [--build-dir DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=build
install=1
while [ $# -gt 0 ]; do
  case "$1" in
    --no-install) install=0 ;;
    --build-dir) build_dir="$2"; shift ;;
    -h|--help) sed -n '2,3p' "$0"; exit 0 ;;
    *) echo "setup.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done

# Every package the build, the tests and the GL reference need (../shared/platform-notes.md);
# GNU parallel for the shard test and Slurm (slurmctld, slurmd, munge) for the cluster test
# (docs/shards.md); gdb to stop a render mid-write for the CLI test's SIGKILL checks; the label font of `aquarelle grid`
# (docs/grid.md); git for the commit recorded in provenance manifests (docs/provenance.md).
pkgs=(build-essential cmake ninja-build pkg-config
      libglm-dev libtinygltf-dev libopenimageio-dev libtbb-dev libbenchmark-dev libgtest-dev
      nlohmann-json3-dev libssl-dev libdeflate-dev libisal-dev libjpeg62-turbo-dev libpng-dev
      libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
      parallel fonts-dejavu-core git
      slurmctld slurmd slurm-client munge gdb
      libboost-dev chromium chromium-driver python3-selenium
      pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-pil
      python3-nbclient python3-nbformat python3-ipykernel python3-matplotlib)
# pybind11 and NumPy for the Python module, pytest, Pillow, nbclient, ipykernel and Matplotlib for
# its tests and the example notebook (docs/python.md). Boost.Beast for `aquarelle serve`; headless Chromium, its driver and Selenium for the browser test
# of its page (docs/serve.md). The page's UI package comes from npm (app/web/package-lock.json):
# Node.js is installed from Debian unless an npm is already there (a NodeSource nodejs bundles
# its own npm and conflicts with Debian's).
command -v npm >/dev/null || pkgs+=(nodejs npm)

[ "$install" = 1 ] && bash scripts/install_packages.sh setup "${pkgs[@]}"

gen=()
command -v ninja >/dev/null && gen=(-G Ninja)
if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  cmake -S . -B "$build_dir" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release
fi
cmake --build "$build_dir" --parallel "$(nproc)"
echo "setup: built into $build_dir/"
# The Python module into Debian's /usr/local site folder, so `/usr/bin/python3 -c "import aquarelle"`
# works (docs/python.md); without the rights to write there, the build's copy is used through
# PYTHONPATH.
if [ "$install" = 1 ] && grep -q "^AQ_BUILD_PYTHON:BOOL=ON" "$build_dir/CMakeCache.txt"; then
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo -n"
  if $sudo_cmd cmake --install "$build_dir" --component python >/dev/null; then
    echo "setup: Python module installed (import aquarelle)"
  else
    echo "setup: could not install the Python module; use PYTHONPATH=$PWD/$build_dir/python" >&2
  fi
fi
