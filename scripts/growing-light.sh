#!/usr/bin/env bash
# The growing-light study of the VWSS paper (Marrs et al. 2018, Fig. 8: the light grows to 64 times
# its area, one light sample per 2 units of area, 8 to 512 samples) on the built-in `growing` scene
# (the creature under an overhead light): the light's side grows by sqrt(2) a step, 1x to 8x (its
# area 1x to 64x), with 8 x 2^k light samples, so the samples per unit of light area stay constant;
# vwss and mvr run with those samples at every step, against the ray-traced ground truth.
#   scripts/growing-light.sh PENUMBRA_BINARY [OUT_DIR] [RUNS]
# Writes OUT_DIR/growing.jsonl (the bench rows, with light_scale and light_area_ratio added),
# OUT_DIR/growing.svg (time and RMSE of V against the light's area) and OUT_DIR/growing.md (the table).
set -euo pipefail
bin=$(readlink -f "${1:?usage: growing-light.sh PENUMBRA_BINARY [OUT_DIR] [RUNS]}")
dir=${2:-out/growing-light}
runs=${3:-3}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$dir"
: > "$dir/growing.jsonl"
for k in 0 1 2 3 4 5 6; do
  scale=$(python3 -c "print(2 ** ($k / 2))")
  n=$((8 << k))
  echo "growing light: step $k, side x$scale, $n light samples" >&2
  "$bin" bench shadows --scene growing --light-scale "$scale" --setting "vwss:views=$n" --setting "mvr:views=$n" \
    --runs "$runs" --json --out "$dir/step$k" --cache "$dir/gt-cache" |
    grep '^{' | sed "s/^{/{\"light_scale\": $scale, \"light_area_ratio\": $((1 << k)), /" >> "$dir/growing.jsonl"
done
python3 "$here/growing-light-figure.py" "$dir/growing.jsonl" "$dir/growing.svg" > "$dir/growing.md"
cat "$dir/growing.md"
