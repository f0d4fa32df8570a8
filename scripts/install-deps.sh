#!/usr/bin/env bash
# Installs the Debian 12 packages Penumbra needs, only those that are missing.
# Runs apt-get as root, or through sudo when not root.
set -euo pipefail
pkgs=(g++ cmake ninja-build pkg-config git
      libglm-dev libtbb-dev libhwy-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libembree-dev
      libopenimageio-dev libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev
      python3-dev pybind11-dev python3-numpy python3-pytest  # the Python module and its tests
      clang-14 libclang-rt-14-dev)  # the fuzz targets (scripts/fuzz.sh): libFuzzer
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
echo "penumbra: installing missing Debian packages: ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
