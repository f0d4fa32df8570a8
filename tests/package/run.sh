#!/usr/bin/env bash
# The package test: installs the build tree BUILD into a fresh prefix, configures tests/package/
# consumer against it with find_package(Penumbra CONFIG REQUIRED), builds and runs it.
#   tests/package/run.sh BUILD_DIR WORK_DIR
set -euo pipefail
build=$(readlink -f "${1:?usage: run.sh BUILD_DIR WORK_DIR}")
work=${2:?usage: run.sh BUILD_DIR WORK_DIR}
src=$(dirname "$(readlink -f "$0")")/consumer
rm -rf "$work"
mkdir -p "$work"
work=$(readlink -f "$work")
cmake --install "$build" --prefix "$work/prefix" >/dev/null
# lib, lib64 or lib/<multiarch>: wherever GNUInstallDirs put the package.
config=$(find "$work/prefix" -name PenumbraConfig.cmake -path '*/cmake/Penumbra/*' | head -n 1)
test -n "$config"
test -f "$(dirname "$config")/PenumbraConfigVersion.cmake"
test -f "$work/prefix/include/penumbra/engine/renderer.h"
# The compiler and build type of the build tree (a sanitized build's libraries need its flags).
cxx=$(sed -n 's/^CMAKE_CXX_COMPILER:[A-Z]*=//p' "$build/CMakeCache.txt")
type=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$build/CMakeCache.txt")
cmake -S "$src" -B "$work/build" -G Ninja -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE="${type:-Release}" \
  -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/build" -j"${PENUMBRA_JOBS:-2}" >/dev/null
# The image module installed where the engine looks for it; the consumer uses this one (not the
# build tree's, which it would find too).
module=$(find "$work/prefix" -name libpenumbra_image_oiio.so -path '*/penumbra/*' | head -n 1)
test -n "$module"
PENUMBRA_IMAGE_MODULE="$module" "$work/build/consumer" "$work"
test -f "$work/consumer.exr"
rm -rf "$work"
