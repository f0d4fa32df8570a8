"""Scene.add_mesh and friends: every bad array raises penumbra.Error naming the argument."""
import numpy as np
import pytest

import penumbra
from conftest import ground

V, T = ground()


@pytest.mark.parametrize(
    "vertices, triangles, match",
    [
        (V[:, :2], T, r"vertices: expected shape \(N, 3\)"),
        (V.ravel(), T, r"vertices: expected shape \(N, 3\)"),
        (np.array([[0, 0, np.nan]] * 4, dtype=np.float32), T, "vertices: row 0 is not finite"),
        (np.where(np.arange(12).reshape(4, 3) == 7, np.inf, V), T, "vertices: row 2 is not finite"),
        (V, np.array([[0, 1, 4]]), "triangles: triangle 0 has index 4, out of range"),
        (V, np.array([[0, -1, 2]]), "index -1, out of range"),
        (V, np.array([[0, 1, 2]], dtype=np.uint64) + np.uint64(2**63), "out of range"),
        (V, T.astype(np.float32), "triangles: expected integer indices"),
        (V, T[:, :2], r"triangles: expected shape \(N, 3\)"),
        (None, T, "vertices: expected an array, got None"),
        ("abc", T, "vertices"),
        (np.array([["a", "b", "c"]]), T, "vertices: expected numbers"),
        (V.astype(object), T, "vertices"),
    ],
)
def test_bad_mesh_arrays(vertices, triangles, match):
    s = penumbra.Scene()
    with pytest.raises(penumbra.Error, match=match):
        s.add_mesh(vertices, triangles)
    assert s.mesh_count == 0  # nothing half-added


def test_bad_optional_arrays():
    s = penumbra.Scene()
    with pytest.raises(penumbra.Error, match="normals: 3 rows, expected one per vertex"):
        s.add_mesh(V, T, normals=V[:3])
    with pytest.raises(penumbra.Error, match="uvs"):
        s.add_mesh(V, T, uvs=V)
    with pytest.raises(penumbra.Error, match="colors: row 1 is not finite"):
        s.add_mesh(V, T, colors=np.array([[1, 1, 1], [np.nan, 0, 0], [0, 0, 0], [0, 0, 0]]))
    with pytest.raises(penumbra.Error, match="color: expected 3 or 4 numbers"):
        s.add_mesh(V, T, color=(1, 1))
    with pytest.raises(penumbra.Error, match=r"transform: expected shape \(4, 4\)"):
        s.add_mesh(V, T, transform=np.eye(3))
    with pytest.raises(penumbra.Error, match="transform: row 0 is not finite"):
        s.add_mesh(V, T, transform=np.full((4, 4), np.nan))
    with pytest.raises(penumbra.Error, match="mesh 5 out of range"):
        s.add_instance(5)
    with pytest.raises(penumbra.Error, match="eye: expected 3 numbers"):
        s.set_camera(eye=(0, 1), target=(0, 0, 0))
    with pytest.raises(penumbra.Error, match="add_area_light"):
        s.add_area_light(center=(0, 1, 0), facing=(0, 0, 0))
    with pytest.raises(penumbra.Error, match="add_area_light"):
        s.add_area_light(center=(0, 1, 0), facing=(0, -1, 0), width=-1)
    with pytest.raises(penumbra.Error, match="intensity"):
        s.add_point_light(position=(0, 1, 0), intensity=-2)
    assert s.mesh_count == 0 and s.instance_count == 0


def test_dtypes_are_converted_and_inputs_copied():
    s = penumbra.Scene()
    v = V.astype(np.float64)
    mesh = s.add_mesh(v, T.astype(np.uint32))
    s.add_mesh(V.astype(np.int64), T.astype(np.int16))
    s.add_mesh(np.asfortranarray(V), T[::1])
    s.add_instance(mesh, transform=np.eye(4) * 2 + np.diag([0, 0, 0, -1]))
    assert s.mesh_count == 3 and s.instance_count == 4 and s.triangle_count == 8
    v[:] = np.nan  # the scene holds its own copy
    s.set_camera(eye=(0, 5, 5), target=(0, 0, 0))
    assert penumbra.render(s, 16, 16, shadow="none")["color"].shape == (16, 16, 4)


def test_empty_meshes_render():
    s = penumbra.Scene()
    s.add_mesh(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.int32))
    s.set_camera(eye=(0, 0, 5), target=(0, 0, 0))
    out = penumbra.render(s, 8, 8, aov=["triangle"])
    assert (out["triangle"] == -1).all()


def test_random_garbage_only_raises_penumbra_error():
    """Arrays of random shapes, dtypes and values (NaN, Inf, huge, negative) into every entry point:
    each call either works or raises penumbra.Error, never anything else, never a crash."""
    rng = np.random.default_rng(1234)
    dtypes = [np.float32, np.float64, np.int8, np.int32, np.int64, np.uint16, np.uint32, np.uint64, np.bool_,
              np.complex64, object]
    specials = np.array([np.nan, np.inf, -np.inf, 1e38, -1e38, 0.0, 1.0, -1.0, 2**31, 2**33])

    def garbage():
        n = int(rng.integers(0, 7))
        shapes = [(n, 3), (n, 3), (n, 4), (n, 2), (4, 4), (3,), (n,), (), (n, 3, 1)]
        shape = shapes[int(rng.integers(0, len(shapes)))]
        a = rng.choice(specials, size=shape) if rng.random() < 0.5 else rng.normal(0, 3, size=shape)
        dt = dtypes[int(rng.integers(0, len(dtypes)))]
        try:
            with np.errstate(all="ignore"):
                return np.asarray(a).astype(dt)
        except (ValueError, OverflowError, TypeError):
            return np.asarray(a)

    calls = rendered = 0
    for _ in range(400):
        s = penumbra.Scene()
        # Half the time well-formed arrays of extreme values (huge, tiny, degenerate): they must render.
        n = int(rng.integers(1, 9))
        good = rng.random() < 0.5
        v = rng.choice(specials[3:], size=(n, 3)) * rng.random((n, 3)) if good else garbage()
        t = rng.integers(0, n, size=(int(rng.integers(0, 5)), 3)) if good else garbage()
        try:
            s.add_mesh(v, t, normals=garbage() if rng.random() < 0.2 else None,
                       colors=garbage() if rng.random() < 0.2 else None,
                       transform=garbage() if rng.random() < 0.2 else None)
            s.set_camera(eye=rng.normal(0, 5, 3) if good else garbage(), target=(0, 0, 0))
            penumbra.render(s, 8, 8, shadow="pcss")
            rendered += 1
        except penumbra.Error:
            pass
        try:
            penumbra.rasterize(garbage(), garbage(), 8, 8)
        except penumbra.Error:
            pass
        try:
            s.set_camera_matrices(garbage(), garbage())
        except penumbra.Error:
            pass
        calls += 1
    assert calls == 400 and rendered > 5  # some garbage is valid and renders
