#!/usr/bin/env python3
"""Writes the measured tables of `penumbra bench stochastic` into the docs.

Usage: scripts/stochastic-bench-tables.py RESULTS_JSON

Reads the report's results.json and replaces, in docs/stochastic.md and docs/performance.md, the
text between <!-- bench:NAME --> and <!-- /bench --> markers: NAME "stochastic" (every row) or
"stochastic-summary" (per scene and method at 16 samples per pixel: tests, STE, time, and the
ratios against the box method measured in the same run).
"""
import json
import pathlib
import re
import sys


def full_table(rows):
    out = ["| scene | method | spp | ms | tests | hits | STE | STE per triangle p10 / median / p90 | RMSE |",
           "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        method = r["method"] + ("" if r["static_path"] else " (static triangles per sample)")
        out.append(f"| {r['scene']} | {method} | {r['spp']} | {r['ms']:.1f} | {r['tests']:,} | {r['hits']:,} | "
                   f"{r['ste']:.3f} | {r['ste_triangle_p10']:.3f} / {r['ste_triangle_median']:.3f} / "
                   f"{r['ste_triangle_p90']:.3f} | {r['rmse']:.5f} |")
    return "\n".join(out)


def summary_table(rows):
    out = ["| scene | method | tests (16 spp) | STE | ms at 4 / 16 / 64 spp | tests vs box | time vs box (16 spp) |",
           "|---|---|---|---|---|---|---|"]
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    for s in scenes:
        mine = [r for r in rows if r["scene"] == s and r["static_path"]]
        box = {r["spp"]: r for r in mine if r["method"] == "box"}
        for m in ["box", "interval", "dual"]:
            by = {r["spp"]: r for r in mine if r["method"] == m}
            if 16 not in by:
                continue
            r = by[16]
            times = " / ".join(f"{by[k]['ms']:.0f}" if k in by else "—" for k in (4, 16, 64))
            tv = f"{r['tests'] / box[16]['tests']:.3f}" if 16 in box else "—"
            mv = f"{r['ms'] / box[16]['ms']:.2f}" if 16 in box else "—"
            out.append(f"| {s} | {m} | {r['tests']:,} | {r['ste']:.3f} | {times} | {tv} | {mv} |")
    return "\n".join(out)


def main():
    data = json.loads(pathlib.Path(sys.argv[1]).read_text())
    rows = data["rows"]
    tables = {"stochastic": full_table(rows), "stochastic-summary": summary_table(rows)}
    root = pathlib.Path(__file__).resolve().parent.parent
    for doc in [root / "docs" / "stochastic.md", root / "docs" / "performance.md"]:
        text = doc.read_text()
        for name, table in tables.items():
            text = re.sub(rf"(<!-- bench:{re.escape(name)} -->\n).*?(<!-- /bench -->)",
                          lambda m: m.group(1) + table + "\n" + m.group(2), text, flags=re.S)
        doc.write_text(text)


if __name__ == "__main__":
    main()
