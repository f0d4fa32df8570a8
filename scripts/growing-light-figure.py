#!/usr/bin/env python3
"""The growing-light figure and table (scripts/growing-light.sh): time and RMSE of V of vwss and mvr
against the light's area, from the bench rows of growing.jsonl. Writes an SVG (no plotting library
needed) and prints a markdown table.

    growing-light-figure.py growing.jsonl growing.svg > growing.md
"""
import json
import math
import sys

rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]
steps = sorted({r["light_area_ratio"] for r in rows})
by = {(r["technique"], r["light_area_ratio"]): r for r in rows}
colors = {"vwss": "#1f77b4", "mvr": "#d62728"}


def panel(x0, title, key, ylabel, log):
    """One plot of `key` against the area ratio (log2 axis), a polyline per technique."""
    w, h, left, bottom = 330, 230, 60, 40
    vals = [by[(t, a)][key] for t in colors for a in steps if (t, a) in by]
    lo, hi = min(vals), max(vals)
    if log:
        lo, hi = math.log10(lo), math.log10(hi)
    pad = (hi - lo) * 0.08 or 1.0
    lo, hi = lo - pad, hi + pad
    def X(a):
        return x0 + left + (math.log2(a) / max(math.log2(steps[-1]), 1)) * (w - left - 10)
    def Y(v):
        v = math.log10(v) if log else v
        return 20 + (1 - (v - lo) / (hi - lo)) * (h - bottom)
    out = [f'<text x="{x0 + w / 2}" y="14" text-anchor="middle" font-size="13">{title}</text>',
           f'<line x1="{x0 + left}" y1="{20 + h - bottom}" x2="{x0 + w - 10}" y2="{20 + h - bottom}" stroke="#444"/>',
           f'<line x1="{x0 + left}" y1="20" x2="{x0 + left}" y2="{20 + h - bottom}" stroke="#444"/>']
    for a in steps:
        out.append(f'<text x="{X(a):.1f}" y="{20 + h - bottom + 15}" text-anchor="middle" font-size="10">{a}x</text>')
    for i in range(5):
        v = lo + (hi - lo) * i / 4
        label = 10 ** v if log else v
        text = f"{label:.0f}" if label >= 100 else f"{label:.3g}"
        y = 20 + (1 - i / 4) * (h - bottom)
        out.append(f'<text x="{x0 + left - 4}" y="{y + 3:.1f}" text-anchor="end" font-size="10">{text}</text>')
        out.append(f'<line x1="{x0 + left}" y1="{y:.1f}" x2="{x0 + w - 10}" y2="{y:.1f}" stroke="#ddd"/>')
    out.append(f'<text x="{x0 + w / 2}" y="{20 + h - 5}" text-anchor="middle" font-size="10">light area '
               f'(samples 8 to {8 * steps[-1]})</text>')
    out.append(f'<text x="{x0 + 12}" y="{20 + (h - bottom) / 2}" font-size="10" '
               f'transform="rotate(-90 {x0 + 12} {20 + (h - bottom) / 2})" text-anchor="middle">{ylabel}</text>')
    for t, c in colors.items():
        pts = [(X(a), Y(by[(t, a)][key])) for a in steps if (t, a) in by]
        out.append('<polyline fill="none" stroke="%s" stroke-width="2" points="%s"/>' %
                   (c, " ".join(f"{x:.1f},{y:.1f}" for x, y in pts)))
        out += [f'<circle cx="{x:.1f}" cy="{y:.1f}" r="3" fill="{c}"/>' for x, y in pts]
    return out


svg = ['<svg xmlns="http://www.w3.org/2000/svg" width="1020" height="290" font-family="sans-serif">',
       '<rect width="100%" height="100%" fill="white"/>']
svg += panel(0, "depth maps, ms (median)", "ms_maps", "ms", True)
svg += panel(340, "total, ms (median)", "ms_total", "ms", True)
svg += panel(680, "RMSE of V against the ground truth", "rmse_v", "RMSE", False)
for i, (t, c) in enumerate(colors.items()):
    svg.append(f'<rect x="{760 + 70 * i}" y="268" width="12" height="12" fill="{c}"/>'
               f'<text x="{776 + 70 * i}" y="278" font-size="11">{t}</text>')
svg.append("</svg>")
with open(sys.argv[2], "w") as f:
    f.write("\n".join(svg) + "\n")

print("| light area | samples | VWSS maps ms | MVR maps ms | maps speed-up | VWSS total ms | MVR total ms | "
      "VWSS RMSE V | MVR RMSE V | RMSE ratio |")
print("|---|---|---|---|---|---|---|---|---|---|")
for a in steps:
    v, m = by.get(("vwss", a)), by.get(("mvr", a))
    if not v or not m:
        continue
    print(f"| {a}x | {8 * a} | {v['ms_maps']:.1f} | {m['ms_maps']:.1f} | {m['ms_maps'] / v['ms_maps']:.1f}x | "
          f"{v['ms_total']:.1f} | {m['ms_total']:.1f} | {v['rmse_v']:.4f} | {m['rmse_v']:.4f} | "
          f"{v['rmse_v'] / m['rmse_v']:.2f} |")
