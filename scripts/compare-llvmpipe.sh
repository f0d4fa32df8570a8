#!/usr/bin/env bash
# Side by side, in one run, interleaved: Mesa's llvmpipe (shared/tools/llvmpipe_bench) and
# `penumbra bench raster` on the WORKLOADS.md meshes, W1 and W2, at 1 and 2 threads.
#   scripts/compare-llvmpipe.sh [rounds]     (default 3 rounds; medians of the per-round medians)
# Needs a Release build (scripts/render.sh) and Debian's libosmesa6-dev (installed if missing).
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-3}
tool=../shared/tools/llvmpipe_bench
bin=$tool/build/llvmpipe_bench
if ! dpkg -s libosmesa6-dev zlib1g-dev >/dev/null 2>&1; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo=sudo
  $sudo apt-get install -y -qq libosmesa6-dev zlib1g-dev >/dev/null
fi
if [ ! -x "$bin" ]; then  # shared/ may be read-only: build beside our own build
  mkdir -p build/llvmpipe_bench
  g++ -O2 -std=c++17 -o build/llvmpipe_bench/llvmpipe_bench $tool/llvmpipe_bench.cpp -lOSMesa -lz -lm
  bin=build/llvmpipe_bench/llvmpipe_bench
fi
penumbra=build/release/apps/penumbra
[ -x "$penumbra" ] || { echo "build first: scripts/render.sh" >&2; exit 2; }
out=$(mktemp)
for r in $(seq "$rounds"); do
  for m in 1000000:synth1m 4000000:synth4m; do
    n=${m%%:*}; name=${m##*:}
    for t in 1 2; do
      GALLIUM_DRIVER=llvmpipe LP_NUM_THREADS=$t $bin --synth "$n" --name "$name" --cull none --frames 10 --min-time 1.0 |
        grep '^RESULT' | sed 's/^/llvmpipe /' >>"$out"
      $penumbra bench raster --synth "$n" --threads "$t" --json 2>/dev/null | sed 's/^/penumbra /' >>"$out"
    done
  done
done
python3 - "$out" <<'PY'
import json, re, statistics, sys
runs = {}
for line in open(sys.argv[1]):
    tool, rest = line.split(' ', 1)
    if tool == 'llvmpipe':
        f = dict(kv.split('=', 1) for kv in rest.split() if '=' in kv)
        key = (f['name'], f['workload'], int(f['threads']))
        ms = float(f['median_ms'])
    else:
        j = json.loads(rest)
        key = (j['name'], j['workload'], j['threads'])
        ms = j['median_ms']
    runs.setdefault((tool,) + key, []).append(ms)
print(f"{'mesh':8} {'workload':8} {'threads':>7} {'llvmpipe ms':>12} {'penumbra ms':>12} {'ratio':>6}")
for (tool, name, wl, th) in sorted(k for k in runs if k[0] == 'llvmpipe'):
    l = statistics.median(runs[(tool, name, wl, th)])
    p = statistics.median(runs.get(('penumbra', name, wl, th), [float('nan')]))
    print(f"{name:8} {wl:8} {th:7d} {l:12.1f} {p:12.1f} {l / p:6.2f}")
for name in sorted({k[1] for k in runs}):
    for wl in ('W1', 'W2'):
        a, b = runs.get(('penumbra', name, wl, 1)), runs.get(('penumbra', name, wl, 2))
        if a and b:
            print(f"penumbra {name} {wl}: 2 threads {statistics.median(a) / statistics.median(b):.2f}x faster than 1")
PY
rm -f "$out"
