#!/usr/bin/env python3
"""Writes the measured tables of `penumbra bench shadows` into the docs.

Usage: scripts/shadow-bench-tables.py RESULTS_JSON [BEFORE_JSON] [--only NAME,NAME...]

Reads the report's results.json and replaces, in docs/techniques/*.md and docs/performance.md,
the text between <!-- bench:NAME --> and <!-- /bench --> markers: NAME is a technique (its rows
on every scene and setting), "overview" (RMSE of V and total time of each technique's defaults
per scene), "vwssmvr" (VWSS against MVR at 24 and 128 maps, defaults), "vwsspaper" (the same in the
VWSS paper's configuration), "curved" (each technique's
defaults on the curved-mesh scenes: ground, object and contact RMSE and bias, BEFORE_JSON's
figures next to RESULTS_JSON's when given) or "curvedNAME" (the same for technique NAME alone).
--only limits the update to the markers named (after a bench of some techniques only).
"""
import json
import pathlib
import re
import sys


def pair(r, kind):
    """RMSE / bias of one receiver class ("ground", "object", "contact"), or a dash."""
    rmse, bias = r.get(f"rmse_v_{kind}"), r.get(f"bias_v_{kind}")
    return "–" if rmse is None or bias is None else f"{rmse:.4f} / {bias:+.4f}"


def technique_table(rows, name):
    out = ["| scene | setting | maps ms | filter ms | evaluate ms | total ms | RMSE V | bias V | ground RMSE / bias | "
           "object RMSE / bias | contact RMSE / bias | > 0.05 | RMSE image |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["technique"] != name:
            continue
        out.append(f"| {r['scene']} | {r['params'] or 'defaults'} | {r['ms_maps']:.1f} | {r['ms_filter']:.1f} | "
                   f"{r['ms_evaluate']:.1f} | {r['ms_total']:.1f} | {r['rmse_v']:.4f} | {r['bias_v']:+.4f} | "
                   f"{pair(r, 'ground')} | {pair(r, 'object')} | {pair(r, 'contact')} | "
                   f"{100 * r['frac_err_gt_005']:.1f}% | {r['rmse_image']:.4f} |")
    return "\n".join(out)


CURVED = ("creature", "knot", "menagerie")


def curved_table(rows, before, only=None):
    """Defaults of each technique on the curved scenes: before -> after per receiver class."""
    out = ["| technique | scene | ground RMSE / bias | object RMSE / bias | contact RMSE / bias | object ÷ ground |",
           "|---|---|---|---|---|---|"]
    techs = []
    for r in rows:
        if r["technique"] not in techs and (only is None or r["technique"] == only):
            techs.append(r["technique"])
    for t in techs:
        for s in CURVED:
            a = [r for r in rows if r["technique"] == t and r["scene"] == s and r["params"] == ""]
            if not a:
                continue
            a = a[0]
            b = [r for r in before if r["technique"] == t and r["scene"] == s and r["params"] == ""] if before else []

            def cell(kind):
                return (pair(b[0], kind) + " → " if b else "") + pair(a, kind)
            ratio = a["rmse_v_object"] / a["rmse_v_ground"] if a.get("rmse_v_ground") else float("nan")
            out.append(f"| {t} | {s} | {cell('ground')} | {cell('object')} | {cell('contact')} | {ratio:.2f} |")
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


def params_of(r):
    """A row's parameters as a dict (the report writes them in the technique's parameter order)."""
    return dict(kv.split("=", 1) for kv in r["params"].split(",") if kv)


def find(rows, scene, technique, params):
    want = {k: str(v) for k, v in params.items()}
    match = [r for r in rows if r["scene"] == scene and r["technique"] == technique and params_of(r) == want]
    return match[0] if match else None


def vwss_table(rows, paper):
    """VWSS against MVR with the same light samples, map size and maps (fitted to the receivers, VWSS's
    default), at 24 and 128 maps: the defaults (surfels, 1 tap, Hammersley points), or with paper=True the VWSS paper's configuration for both
    (its point splat with the slope bias it was measured with, 5-tap PCF, Poisson-disk light samples)."""
    extra_v = {"splat": "point", "pcf": "5", "samples": "poisson", "slope_bias": "0.5"} if paper else {}
    extra_m = {"pcf": "5", "samples": "poisson", "fit": "receivers"} if paper else {"fit": "receivers"}
    out = ["| scene | maps | MVR maps ms | VWSS maps ms (points + splat) | maps speed-up | MVR total ms | "
           "VWSS total ms | total speed-up | MVR RMSE V | VWSS RMSE V | RMSE ratio |",
           "|---|---|---|---|---|---|---|---|---|---|---|"]
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    for s in scenes:
        for views in (24, 128):
            m = find(rows, s, "mvr", {"views": views, **extra_m})
            v = find(rows, s, "vwss", {"views": views, **extra_v})
            if not m or not v:
                continue
            spread = lambda r: f"<br><small>{r['ms_maps_min']:.1f}–{r['ms_maps_max']:.1f}</small>" if "ms_maps_min" in r else ""
            parts = f" ({v.get('ms_points', 0):.1f} + {v.get('ms_splat', 0):.1f})" if v.get("ms_points") else ""
            out.append(f"| {s} | {views} | {m['ms_maps']:.1f}{spread(m)} | {v['ms_maps']:.1f}{parts}{spread(v)} | "
                       f"{m['ms_maps'] / v['ms_maps']:.1f}x | {m['ms_total']:.1f} | {v['ms_total']:.1f} | "
                       f"{m['ms_total'] / v['ms_total']:.1f}x | {m['rmse_v']:.4f} | {v['rmse_v']:.4f} | "
                       f"{v['rmse_v'] / m['rmse_v']:.2f} |")
    return "\n".join(out)


def main():
    args = sys.argv[1:]
    only = None
    if "--only" in args:  # --only NAME,NAME: just those markers (a bench of some techniques only)
        i = args.index("--only")
        only = set(args[i + 1].split(","))
        del args[i:i + 2]
    if len(args) not in (1, 2):
        sys.exit(__doc__)
    data = json.loads(pathlib.Path(args[0]).read_text())
    rows = data["rows"] if isinstance(data, dict) else data
    before = None
    if len(args) == 2:
        b = json.loads(pathlib.Path(args[1]).read_text())
        before = b["rows"] if isinstance(b, dict) else b
    root = pathlib.Path(__file__).resolve().parent.parent
    pattern = re.compile(r"(<!-- bench:([a-z0-9]+) -->\n).*?(<!-- /bench -->)", re.S)
    for path in list((root / "docs" / "techniques").glob("*.md")) + [root / "docs" / "performance.md"]:
        text = path.read_text()

        def repl(m):
            name = m.group(2)
            if only is not None and name not in only:
                return m.group(0)
            if name == "overview":
                table = overview_table(rows)
            elif name == "vwssmvr":
                table = vwss_table(rows, paper=False)
            elif name == "vwsspaper":
                table = vwss_table(rows, paper=True)
            elif name == "curved":
                table = curved_table(rows, before)
            elif name.startswith("curved"):
                table = curved_table(rows, before, name[len("curved"):])
            else:
                table = technique_table(rows, name)
            return m.group(1) + table + "\n" + m.group(3)

        new = pattern.sub(repl, text)
        if new != text:
            path.write_text(new)
            print(f"updated {path.relative_to(root)}")


if __name__ == "__main__":
    main()
