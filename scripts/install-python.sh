#!/usr/bin/env bash
# Installs the Python module built in BUILD (default build/release) for the current user: copies
# BUILD/python/penumbra into the user site-packages of the python3 it was built for (Debian's
# /usr/bin/python3), so that `python3 -c "import penumbra"` works from any folder. Run by
# scripts/render.sh and scripts/test.sh after they build it.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build/release}
pkg="$build/python/penumbra"
if ! ls "$pkg"/_penumbra*.so >/dev/null 2>&1; then
  echo "install-python.sh: $pkg has no built module (build the _penumbra target first)" >&2
  exit 2
fi
py=$(sed -n 's/^Python_EXECUTABLE:[A-Z]*=//p' "$build/CMakeCache.txt")
py=${py:-/usr/bin/python3}
site=$("$py" -c 'import site; print(site.getusersitepackages())')
mkdir -p "$site"
rm -rf "$site/penumbra.tmp"
cp -r "$pkg" "$site/penumbra.tmp"
rm -rf "$site/penumbra"
mv "$site/penumbra.tmp" "$site/penumbra"
echo "penumbra: Python module installed in $site/penumbra (for $py)" >&2
