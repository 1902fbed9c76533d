#!/usr/bin/env bash
# Installs those of the given Debian packages that are missing (idempotent): apt-get as root, or
# through sudo. Shared by scripts/setup.sh and scripts/fuzz.sh.
# Usage: scripts/install_packages.sh LABEL PACKAGE...
set -euo pipefail
label=$1; shift
missing=()
for p in "$@"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "$label: all Debian packages present"
  exit 0
fi
echo "$label: installing ${missing[*]}"
sudo_cmd=""
[ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
$sudo_cmd apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
