#!/usr/bin/env bash
# Installs the Debian 12 packages Penumbra needs, only those that are missing.
# Runs apt-get as root, or through sudo when not root.
#   --browser  also Chromium, for the browser test of the bench reports; where it cannot be
#              installed the test is skipped (with a message), not failed.
set -euo pipefail
browser=0
[ "${1:-}" = --browser ] && browser=1
pkgs=(g++ cmake ninja-build pkg-config git
      libglm-dev libtbb-dev libhwy-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libembree-dev
      libopenimageio-dev zlib1g-dev libcli11-dev libgtest-dev libgmock-dev libbenchmark-dev
      python3-dev pybind11-dev python3-numpy python3-pytest  # the Python module and its tests
      clang-14 libclang-rt-14-dev)  # the fuzz targets (scripts/fuzz.sh): libFuzzer
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
if [ ${#missing[@]} -gt 0 ]; then
  echo "penumbra: installing missing Debian packages: ${missing[*]}" >&2
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
if [ "$browser" = 1 ] && ! dpkg-query -W -f='${Status}' chromium 2>/dev/null | grep -q "install ok installed"; then
  echo "penumbra: installing chromium (the browser test of the bench reports)" >&2
  { $sudo apt-get update -qq && $sudo apt-get install -y -qq --no-install-recommends chromium >/dev/null; } ||
    echo "penumbra: chromium could not be installed: the browser test will be skipped" >&2
fi
