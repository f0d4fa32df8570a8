#!/usr/bin/env python3
"""Writes the measured tables of `penumbra bench shadows` into the docs.

Usage: scripts/shadow-bench-tables.py RESULTS_JSON

Reads the report's results.json and replaces, in docs/techniques/*.md and docs/performance.md,
the text between <!-- bench:NAME --> and <!-- /bench --> markers: NAME is a technique (its rows
on every scene and setting), "overview" (RMSE of V and total time of each technique's defaults
per scene) or "vwssmvr" (VWSS against MVR at 24 and 128 maps).
"""
import json
import pathlib
import re
import sys


def technique_table(rows, name):
    out = ["| scene | setting | maps ms | filter ms | evaluate ms | total ms | RMSE V | max err V | > 0.05 | RMSE image |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["technique"] != name:
            continue
        out.append(f"| {r['scene']} | {r['params'] or 'defaults'} | {r['ms_maps']:.1f} | {r['ms_filter']:.1f} | "
                   f"{r['ms_evaluate']:.1f} | {r['ms_total']:.1f} | {r['rmse_v']:.4f} | {r['max_err_v']:.3f} | "
                   f"{100 * r['frac_err_gt_005']:.1f}% | {r['rmse_image']:.4f} |")
    return "\n".join(out)


def overview_table(rows):
    scenes, techs = [], []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
        if r["technique"] not in techs:
            techs.append(r["technique"])
    out = ["| technique (defaults): RMSE of V / total ms | " + " | ".join(scenes) + " |",
           "|---|" + "---|" * len(scenes)]
    for t in techs:
        cells = []
        for s in scenes:
            match = [r for r in rows if r["technique"] == t and r["scene"] == s and r["params"] == ""]
            cells.append(f"{match[0]['rmse_v']:.3f} / {match[0]['ms_total']:.0f}" if match else "")
        out.append(f"| {t} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def vwss_table(rows):
    """VWSS against MVR with the same light samples and map size, at 24 and 128 maps."""
    out = ["| scene | maps | MVR maps ms | VWSS maps ms | maps speed-up | MVR total ms | VWSS total ms | "
           "MVR RMSE V | VWSS RMSE V | RMSE ratio |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    for s in scenes:
        for views in (24, 128):
            m = [r for r in rows if r["scene"] == s and r["technique"] == "mvr" and r["params"] == f"views={views}"]
            v = [r for r in rows if r["scene"] == s and r["technique"] == "vwss" and r["params"] == f"views={views}"]
            if not m or not v:
                continue
            m, v = m[0], v[0]
            out.append(f"| {s} | {views} | {m['ms_maps']:.1f} | {v['ms_maps']:.1f} | {m['ms_maps'] / v['ms_maps']:.2f}x | "
                       f"{m['ms_total']:.1f} | {v['ms_total']:.1f} | {m['rmse_v']:.4f} | {v['rmse_v']:.4f} | "
                       f"{v['rmse_v'] / m['rmse_v']:.2f} |")
    return "\n".join(out)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    data = json.loads(pathlib.Path(sys.argv[1]).read_text())
    rows = data["rows"] if isinstance(data, dict) else data
    root = pathlib.Path(__file__).resolve().parent.parent
    pattern = re.compile(r"(<!-- bench:([a-z0-9]+) -->\n).*?(<!-- /bench -->)", re.S)
    for path in list((root / "docs" / "techniques").glob("*.md")) + [root / "docs" / "performance.md"]:
        text = path.read_text()

        def repl(m):
            name = m.group(2)
            if name == "overview":
                table = overview_table(rows)
            elif name == "vwssmvr":
                table = vwss_table(rows)
            else:
                table = technique_table(rows, name)
            return m.group(1) + table + "\n" + m.group(3)

        new = pattern.sub(repl, text)
        if new != text:
            path.write_text(new)
            print(f"updated {path.relative_to(root)}")


if __name__ == "__main__":
    main()
