#!/usr/bin/env python3
"""A mesh made with NumPy, rendered with soft shadows, and what each pixel saw.

    python3 examples/mesh_from_numpy.py [OUT_DIR]

Writes OUT_DIR/mesh.png (the image) and OUT_DIR/mesh-triangles.png (the triangle id per pixel as
false colour) and prints how many pixels each instance covers.
"""
import os
import sys

import numpy as np

import penumbra


def wavy_disc(rings=48, segments=96):
    """A height field over a disc: vertices N x 3, triangles M x 3, colors N x 3."""
    r = np.linspace(0.0, 1.0, rings + 1)[1:]
    a = np.linspace(0.0, 2.0 * np.pi, segments, endpoint=False)
    rr, aa = np.meshgrid(r, a, indexing="ij")
    x, z = rr * np.cos(aa), rr * np.sin(aa)
    y = 0.15 * np.sin(6.0 * rr) * np.cos(3.0 * aa)
    v = np.concatenate([[[0.0, 0.0, 0.0]], np.stack([x, y, z], axis=-1).reshape(-1, 3)])
    tris = [[0, 1 + (j + 1) % segments, 1 + j] for j in range(segments)]
    for i in range(rings - 1):
        for j in range(segments):
            a0, a1 = 1 + i * segments + j, 1 + i * segments + (j + 1) % segments
            b0, b1 = a0 + segments, a1 + segments
            tris += [[a0, a1, b1], [a0, b1, b0]]
    colors = 0.5 + 0.5 * np.stack([np.cos(3 * v[:, 0]), np.cos(3 * v[:, 2]), np.ones(len(v))], axis=1)
    return (2.0 * v).astype(np.float32), np.array(tris, dtype=np.int32), colors.astype(np.float32)


def main():
    out_dir = sys.argv[1] if len(sys.argv) > 1 else "."
    os.makedirs(out_dir, exist_ok=True)
    scene = penumbra.Scene("numpy")
    v, t, c = wavy_disc()
    scene.add_mesh(v, t, colors=c, name="disc")
    # A box, 4 vertices per face so that each face is flat, placed twice.
    quads = []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            u, w = [(1, 2), (2, 0), (0, 1)][axis]
            for du, dw in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = np.zeros(3)
                p[axis], p[u], p[w] = sign, du * sign, dw
                quads.append(0.3 * p)
    corners = np.array(quads, np.float32)
    faces = np.array([[4 * f, 4 * f + 1, 4 * f + 2] for f in range(6)] + [[4 * f, 4 * f + 2, 4 * f + 3] for f in range(6)],
                     np.int32)
    box = scene.add_mesh(corners, faces, color=(0.9, 0.9, 0.85), place=False, name="box")
    for x, y, z in ((-0.7, 0.35, 0.3), (0.6, 0.5, -0.2)):
        m = np.eye(4, dtype=np.float32)
        m[:3, 3] = (x, y, z)
        scene.add_instance(box, transform=m)
    scene.add_area_light(center=(-2.0, 4.0, 2.0), facing=(2.0, -4.0, -2.0), width=1.2, height=1.2, intensity=12.0)
    scene.set_sky(sky=(0.25, 0.28, 0.35), ground=(0.08, 0.07, 0.06))
    scene.set_camera(eye=(0.0, 3.2, 4.2), target=(0.0, 0.2, 0.0), fov=40)

    out = penumbra.render(scene, 640, 360, shadow="pcss", aov=["instance", "triangle"])
    penumbra.write_image(os.path.join(out_dir, "mesh.png"), out["color"])
    tri = out["triangle"]
    false_colour = np.zeros(tri.shape + (3,), np.uint8)
    hit = tri >= 0
    false_colour[hit] = np.stack([(tri[hit] * 67) % 256, (tri[hit] * 131) % 256, (tri[hit] * 29) % 256], axis=1)
    penumbra.write_image(os.path.join(out_dir, "mesh-triangles.png"), false_colour)
    for i in range(scene.instance_count):
        print(f"instance {i}: {(out['instance'] == i).sum()} pixels")
    print(f"background: {(~hit).sum()} pixels")


if __name__ == "__main__":
    main()
