#!/usr/bin/env bash
# Instructions per triangle of each raster stage in one W1 frame on one thread (callgrind):
#   scripts/callgrind-stages.sh build/release/apps/penumbra [TRIANGLES] [W1|W2]
# (TRIANGLES: the synthetic mesh's size, default 1000000.) Takes ~20 s for 1M triangles.
#
# Valgrind 3.19 (Debian 12) cannot decode RDTSCP, which libhwy 1.0.3's load-time initializer runs
# in hwy::platform::TimerResolution; a preloaded shim defines that function and
# InvariantTicksPerSecond (Penumbra times itself with std::chrono, never with these). Valgrind
# reports no AVX-512 to the program, so Highway's dispatch runs the AVX2 target.
set -euo pipefail
bin=$(readlink -f "${1:?usage: callgrind-stages.sh PENUMBRA_BINARY [TRIANGLES] [W1|W2]}")
tris=${2:-1000000}
workload=${3:-W1}
command -v valgrind >/dev/null || { echo "callgrind-stages.sh: valgrind is not installed (apt-get install valgrind)" >&2; exit 2; }
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
cat > "$dir/shim.cpp" <<'EOF'
#include <cstdint>
namespace hwy::platform {
uint64_t TimerResolution() { return 1; }
double InvariantTicksPerSecond() { return 1e9; }
}  // namespace hwy::platform
EOF
c++ -O2 -shared -fPIC "$dir/shim.cpp" -o "$dir/libhwyshim.so"
LD_PRELOAD="$dir/libhwyshim.so" valgrind --tool=callgrind --callgrind-out-file="$dir/cg.out" \
  "$bin" bench raster --synth "$tris" --threads 1 --workload "$workload" --frames 1 --min-time 0 --json \
  > "$dir/bench.json" 2> "$dir/valgrind.log" || { tail -20 "$dir/valgrind.log" >&2; exit 1; }
callgrind_annotate --inclusive=yes "$dir/cg.out" > "$dir/annotate.txt"
python3 - "$dir/cg.out" "$dir/annotate.txt" "$dir/bench.json" <<'EOF'
import json, re, sys
cg, annotate, bench = sys.argv[1:4]
run = next(json.loads(l) for l in open(bench) if l.startswith('{'))
# Frames drawn: calls of Rasterizer::runBatches (the bench's warm-up frames included).
names, frames, callee = {}, 0, None
for line in open(cg):
    m = re.match(r'c?fn=\((\d+)\)(?: (.*))?', line)
    if m:
        if m.group(2): names[m.group(1)] = m.group(2)
        callee = m.group(1) if line.startswith('cfn') else None
        continue
    m = re.match(r'calls=(\d+)', line)
    if m and callee is not None:
        if names.get(callee, '').startswith('penumbra::raster::Rasterizer::runBatches('): frames += int(m.group(1))
        callee = None
incl = {}
for line in open(annotate):
    m = re.match(r'\s*([\d,]+) \([ \d.]+%\)\s+\S*?:(.*)', line)
    if m:
        name = m.group(2)
        incl[name] = max(incl.get(name, 0), int(m.group(1).replace(',', '')))
def total(prefix):
    return max((v for k, v in incl.items() if k.startswith(prefix)), default=0)
per = lambda v: v / frames / run['tris']
vertex = total('void penumbra::raster::Rasterizer::vertexStage<')
front = total('penumbra::raster::Rasterizer::frontEnd(')
assemble = total('penumbra::raster::assembleTriangles(')
setup = total('penumbra::raster::N_AVX2::SetupLanesImpl(') + total('penumbra::raster::setupTriangle(')
tile = total('penumbra::raster::Rasterizer::tileStage(')
print(f"synth {run['tris']} triangles, {run['workload']}, {frames} frames, AVX2 target: instructions per triangle")
print("| stage | instructions / triangle |\n|---|---:|")
for label, v in [("vertex stage (user functor, projection, flags)", vertex),
                 ("assembly + setup", assemble), ("  of which setup", setup),
                 ("front end rest: binning, chunk bookkeeping", front - assemble),
                 ("tile stage (and fragment stage for W2)", tile),
                 ("total", vertex + front + tile)]:
    print(f"| {label} | {per(v):.0f} |")
EOF
