#!/usr/bin/env bash
# Installs what is missing (Debian 12 packages), builds a Release build of the command line and the
# Python module (installed for the user: `python3 -c "import penumbra"`) and renders the built-in
# default scene to out/default.png. Extra arguments go to `penumbra render`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DPENUMBRA_BUILD_TESTS=OFF >/dev/null
cmake --build build/release -j2 --target penumbra _penumbra
scripts/install-python.sh build/release
mkdir -p out
./build/release/apps/penumbra render --builtin default -o out/default.png "$@"
