import numpy as np
import pytest

import penumbra


def sphere(rings=24, segments=48, radius=1.0):
    """A UV sphere as arrays: vertices N x 3 float32, triangles M x 3 int32, normals."""
    th = np.linspace(0.0, np.pi, rings + 1)
    ph = np.linspace(0.0, 2.0 * np.pi, segments + 1)
    t, p = np.meshgrid(th, ph, indexing="ij")
    n = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], axis=-1).reshape(-1, 3)
    tris = []
    for i in range(rings):
        for j in range(segments):
            a, b = i * (segments + 1) + j, (i + 1) * (segments + 1) + j
            tris += [[a, b, a + 1], [a + 1, b, b + 1]]
    return (radius * n).astype(np.float32), np.array(tris, dtype=np.int32), n.astype(np.float32)


def ground(size=8.0):
    v = np.array([[-size, 0, -size], [size, 0, -size], [size, 0, size], [-size, 0, size]], dtype=np.float32)
    return v, np.array([[0, 2, 1], [0, 3, 2]], dtype=np.int32)


def translate(x, y, z):
    m = np.eye(4, dtype=np.float32)
    m[:3, 3] = (x, y, z)
    return m


@pytest.fixture
def ball_scene():
    """A sphere resting on a ground plane under a square area light."""
    s = penumbra.Scene("ball")
    gv, gt = ground()
    s.add_mesh(gv, gt, color=(0.7, 0.7, 0.7), name="ground")
    v, t, n = sphere()
    s.add_mesh(v, t, normals=n, color=(0.9, 0.3, 0.2), transform=translate(0, 1, 0), name="ball")
    s.add_area_light(center=(1.0, 5.0, 0.5), facing=(0, -1, 0), width=1.5, height=1.5, intensity=3.0)
    s.set_camera(eye=(0.0, 3.0, 6.0), target=(0.0, 0.7, 0.0), fov=40)
    return s
