#!/usr/bin/env python3
"""Every shadow technique on one scene against the ray-traced reference: time and error of V.

    python3 examples/compare_shadows.py [SCENE] [OUT_DIR]

SCENE is a built-in scene (default: creature) or a glTF / scene file. Prints a table (time, RMSE
and bias of V on every receiver); with matplotlib installed also writes OUT_DIR/compare.png (V of
each technique and its error), otherwise one PNG of V per technique.
"""
import os
import sys
import time

import numpy as np

import penumbra


def load(name):
    return penumbra.load(name) if ("." in name or "/" in name) else penumbra.builtin(name)


def main():
    name = sys.argv[1] if len(sys.argv) > 1 else "creature"
    out_dir = sys.argv[2] if len(sys.argv) > 2 else "."
    os.makedirs(out_dir, exist_ok=True)
    scene = load(name)
    size = (320, 180)
    ref = penumbra.render(scene, *size, shadow="reference", aov=["visibility"])["visibility"]
    hit = np.isfinite(ref)
    rows, images = [], {}
    for t in penumbra.techniques():
        if t["name"] == "reference":
            continue
        start = time.perf_counter()
        v = penumbra.render(scene, *size, shadow=t["name"], aov=["visibility"])["visibility"]
        ms = 1000 * (time.perf_counter() - start)
        d = v[hit] - ref[hit]
        rows.append((t["name"], ms, np.sqrt(np.mean(d * d)), np.mean(d)))
        images[t["name"]] = v
    print(f"{name}: V against the reference on {hit.sum()} receivers, {size[0]}x{size[1]}")
    print(f"{'technique':10} {'ms':>8} {'RMSE':>7} {'bias':>7}")
    for n, ms, rmse, bias in rows:
        print(f"{n:10} {ms:8.1f} {rmse:7.4f} {bias:+7.4f}")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        for n, v in images.items():
            g = (np.nan_to_num(np.clip(v, 0, 1), nan=0.0) * 255).astype(np.uint8)
            penumbra.write_image(os.path.join(out_dir, f"compare-{n}.png"), np.repeat(g[..., None], 3, axis=2))
        print(f"matplotlib is not installed: wrote {len(images)} PNGs of V to {out_dir}")
        return
    fig, ax = plt.subplots(2, len(images), figsize=(2.2 * len(images), 3.2))
    for i, (n, v) in enumerate(images.items()):
        ax[0, i].imshow(v, cmap="gray", vmin=0, vmax=1)
        ax[1, i].imshow(v - ref, cmap="coolwarm", vmin=-0.5, vmax=0.5)
        ax[0, i].set_title(n, fontsize=8)
        for a in ax[:, i]:
            a.axis("off")
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "compare.png"), dpi=120)
    print(f"wrote {os.path.join(out_dir, 'compare.png')}")


if __name__ == "__main__":
    main()
