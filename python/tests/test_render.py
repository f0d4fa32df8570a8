"""penumbra.render: arrays' shapes and dtypes, what they hold, determinism, the GIL, errors."""
import threading

import numpy as np
import pytest

import penumbra
from conftest import ground, sphere, translate


def test_version_and_listings():
    assert penumbra.__version__.count(".") == 2
    names = [t["name"] for t in penumbra.techniques()]
    assert "pcss" in names and "reference" in names
    pcss = next(t for t in penumbra.techniques() if t["name"] == "pcss")
    assert all({"name", "kind", "default"} <= set(p) for p in pcss["params"])
    assert "default" in [b["name"] for b in penumbra.builtins()]
    assert penumbra.aov_names() == ["visibility", "depth", "position", "normal", "geometric_normal", "albedo",
                                    "instance", "triangle", "barycentrics"]


def test_shapes_and_dtypes(ball_scene):
    out = penumbra.render(ball_scene, 96, 64, aov=["all"], stats=True)
    assert out["color"].shape == (64, 96, 4) and out["color"].dtype == np.uint8
    assert out["linear"].shape == (64, 96, 4) and out["linear"].dtype == np.float32
    for k in ("visibility", "depth"):
        assert out[k].shape == (64, 96) and out[k].dtype == np.float32
    for k in ("position", "normal", "geometric_normal", "albedo", "barycentrics"):
        assert out[k].shape == (64, 96, 3) and out[k].dtype == np.float32
    for k in ("instance", "triangle"):
        assert out[k].shape == (64, 96) and out[k].dtype == np.int32
    assert "G-buffer" in out["stats"] or "gbuffer" in out["stats"].lower()
    assert set(penumbra.render(ball_scene, 8, 8).keys()) == {"color", "linear"}


def test_buffers_agree(ball_scene):
    out = penumbra.render(ball_scene, 120, 80, aov=["all"], shadow="mvr", params={"views": 16})
    hit = out["instance"] >= 0
    assert hit.sum() > 2000 and (~hit).sum() > 0  # sky above the horizon
    # Background: NaN floats, -1 ids; hits: finite, ids in range.
    assert np.isnan(out["depth"][~hit]).all() and (out["triangle"][~hit] == -1).all()
    assert np.isfinite(out["position"][hit]).all()
    assert set(np.unique(out["instance"][hit])) == {0, 1}
    ball = out["instance"] == 1
    assert (out["triangle"][ball] < 24 * 48 * 2).all() and (out["triangle"][out["instance"] == 0] < 2).all()
    # Barycentrics sum to 1 and rebuild the position on the ball (radius 1 around (0, 1, 0)).
    b = out["barycentrics"][hit]
    assert np.allclose(b.sum(axis=1), 1.0, atol=1e-4) and (b > -1e-4).all()
    r = np.linalg.norm(out["position"][ball] - np.array([0, 1, 0]), axis=1)
    assert np.allclose(r, 1.0, atol=0.01)
    # V in [0, 1], some ground in shadow, normals unit, albedo the mesh colors.
    v = out["visibility"][hit]
    assert ((v >= 0) & (v <= 1)).all() and (v < 0.5).sum() > 50
    assert np.allclose(np.linalg.norm(out["normal"][hit], axis=1), 1.0, atol=1e-4)
    assert np.allclose(out["albedo"][ball], [0.9, 0.3, 0.2], atol=1e-6)
    # Depth grows with distance from the eye.
    d = np.linalg.norm(out["position"][hit] - np.array([0.0, 3.0, 6.0]), axis=1)
    assert np.all(out["depth"][hit] <= d + 1e-3)


def test_same_arrays_at_any_thread_count(ball_scene):
    runs = [penumbra.render(ball_scene, 80, 48, aov=["all"], threads=t) for t in (1, 2, 3)]
    for other in runs[1:]:
        for k in runs[0]:
            assert np.array_equal(runs[0][k], other[k], equal_nan=True), k


def test_vertex_colors_multiply_the_base_color():
    s = penumbra.Scene()
    v, t = ground(1.0)
    colors = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], dtype=np.float32)
    s.add_mesh(v, t, colors=colors, color=(0.5, 0.5, 0.5))
    s.set_camera(eye=(0, 3, 0.01), target=(0, 0, 0), fov=30)
    out = penumbra.render(s, 32, 32, aov=["albedo", "barycentrics", "triangle"], shadow="none")
    hit = out["triangle"] >= 0
    assert hit.all()
    want = np.einsum("hwk,hwkc->hwc", out["barycentrics"], colors[t[out["triangle"]]]) * 0.5
    assert np.allclose(out["albedo"], want, atol=1e-5)


def test_shadows_darken_and_reference_agrees(ball_scene):
    lit = penumbra.render(ball_scene, 64, 40, shadow="none", aov=["visibility"])
    ref = penumbra.render(ball_scene, 64, 40, shadow="reference", params={"samples": 256}, aov=["visibility"])
    pcss = penumbra.render(ball_scene, 64, 40, shadow="pcss", aov=["visibility"])
    hit = np.isfinite(ref["visibility"])
    assert (lit["visibility"][hit] == 1).all()
    assert (ref["color"][..., :3].astype(int) <= lit["color"][..., :3].astype(int) + 1).all()
    err = np.sqrt(np.mean((pcss["visibility"][hit] - ref["visibility"][hit]) ** 2))
    assert err < 0.1


def test_camera_from_matrices_matches_look_at(ball_scene):
    eye, target = np.array([0.0, 3.0, 6.0]), np.array([0.0, 0.7, 0.0])
    f = (target - eye) / np.linalg.norm(target - eye)
    r = np.cross(f, [0, 1, 0])
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    view = np.eye(4)
    view[0, :3], view[1, :3], view[2, :3] = r, u, -f
    view[:3, 3] = -view[:3, :3] @ eye
    n, fa, fov, aspect = 0.5, 40.0, np.radians(40.0), 96 / 64
    proj = np.zeros((4, 4))
    proj[0, 0], proj[1, 1] = 1 / (aspect * np.tan(fov / 2)), 1 / np.tan(fov / 2)
    proj[2, 2], proj[2, 3], proj[3, 2] = -(fa + n) / (fa - n), -2 * fa * n / (fa - n), -1
    ball_scene.set_camera_matrices(view, proj)
    a = penumbra.render(ball_scene, 96, 64, aov=["triangle", "depth"], shadow="none")
    ball_scene.set_camera(eye=eye, target=target, fov=40, near=n, far=fa)
    b = penumbra.render(ball_scene, 96, 64, aov=["triangle", "depth"], shadow="none")
    assert (a["triangle"] == b["triangle"]).mean() > 0.99
    assert np.nanmax(np.abs(a["depth"] - b["depth"])) < 1e-3
    ball_scene.set_camera_matrices(view, proj)
    with pytest.raises(penumbra.Error, match="aspect"):
        penumbra.render(ball_scene, 64, 64)
    with pytest.raises(penumbra.Error, match="symmetric perspective"):
        ball_scene.set_camera_matrices(view, np.eye(4))


def test_the_gil_is_released_while_rendering():
    import time
    scene = penumbra.builtin("knot")
    span = {}

    def work():
        span["start"] = time.perf_counter()
        penumbra.render(scene, 480, 270, shadow="pcss", threads=1)
        span["end"] = time.perf_counter()

    t = threading.Thread(target=work)
    t.start()
    seen = []
    while t.is_alive():
        seen.append(time.perf_counter())
    t.join()
    # This thread ran while the render was in its middle half: with the GIL held by the render it
    # could run only before and after it (the interpreter switches threads between bytecodes).
    a, b = span["start"], span["end"]
    middle = [s for s in seen if a + 0.25 * (b - a) < s < a + 0.75 * (b - a)]
    assert len(middle) > 100


def test_a_scene_cannot_change_while_rendered():
    scene = penumbra.builtin("knot")
    v, t = ground()
    errors = []

    def work():
        penumbra.render(scene, 480, 270, threads=1)

    th = threading.Thread(target=work)
    th.start()
    while th.is_alive():
        try:
            scene.add_mesh(v, t)
        except penumbra.Error as e:
            errors.append(str(e))
            break
    th.join()
    assert errors and "being rendered" in errors[0]


def test_default_light_and_lights():
    s = penumbra.Scene()
    v, t, n = sphere(8, 16)
    s.add_mesh(v, t, normals=n)
    gv, gt = ground()
    s.add_mesh(gv, gt)
    unlit = penumbra.render(s, 32, 24, default_light=False)["linear"]
    lit = penumbra.render(s, 32, 24)["linear"]
    assert lit[..., :3].mean() > 2 * unlit[..., :3].mean()
    assert s.area_light_count == 0  # the default light is not the user's
    s.add_point_light(position=(0, 3, 0), intensity=20.0)
    s.add_directional_light(direction=(0, -1, 0))
    s.set_sky(sky=(0.2, 0.2, 0.3), ground=(0.1, 0.1, 0.1))
    assert penumbra.render(s, 32, 24)["linear"][..., :3].mean() > 0


def test_memory_limit_refuses_before_work(ball_scene):
    with pytest.raises(penumbra.Error, match="memory"):
        penumbra.render(ball_scene, 4000, 4000, max_memory=10_000_000)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"width": 0}, "--width"),
        ({"height": 20000}, "--height"),
        ({"shadow": "nope"}, "nope"),
        ({"params": {"bogus": 1}}, "bogus"),
        ({"params": 3}, "params"),
        ({"spp": 0}, "--spp"),
        ({"threads": -1}, "threads"),
        ({"aov": ["colour"]}, "colour"),
        ({"aov": ["depth", "depth"]}, "twice"),
        ({"tonemap": "filmic"}, "tonemap"),
    ],
)
def test_bad_options_raise(ball_scene, kwargs, match):
    with pytest.raises(penumbra.Error, match=match):
        penumbra.render(ball_scene, **{"width": 16, "height": 16, **kwargs})


def test_load_files(tmp_path):
    import base64
    import json
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
    i = np.array([0, 1, 2], dtype=np.uint16)
    data = v.tobytes() + i.tobytes() + b"\0\0"
    gltf = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 6}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}],
        "scene": 0,
    }
    path = tmp_path / "tri.gltf"
    path.write_text(json.dumps(gltf))
    s = penumbra.load(str(path))
    assert s.triangle_count == 1 and s.instance_count == 1
    out = penumbra.render(s, 32, 32, aov=["triangle"])
    assert (out["triangle"] == 0).sum() > 50
    with pytest.raises(penumbra.Error, match="missing.gltf"):
        penumbra.load(str(tmp_path / "missing.gltf"))
    bad = tmp_path / "bad.gltf"
    bad.write_text("{not json")
    with pytest.raises(penumbra.Error, match="bad.gltf"):
        penumbra.load(str(bad))
    with pytest.raises(penumbra.Error, match="nope"):
        penumbra.builtin("nope")


def test_write_image(tmp_path):
    img = np.zeros((4, 6, 3), np.uint8)
    img[1, 2] = (255, 0, 0)
    penumbra.write_image(str(tmp_path / "a.png"), img)
    assert (tmp_path / "a.png").read_bytes()[:4] == b"\x89PNG"
    penumbra.write_image(str(tmp_path / "a.exr"), np.ones((4, 6), np.float32))
    assert (tmp_path / "a.exr").stat().st_size > 0
    with pytest.raises(penumbra.Error, match="OpenEXR"):
        penumbra.write_image(str(tmp_path / "b.png"), np.ones((4, 6, 3), np.float32))
    with pytest.raises(penumbra.Error, match="shape"):
        penumbra.write_image(str(tmp_path / "c.png"), np.ones((4,), np.uint8))
    with pytest.raises(penumbra.Error):
        penumbra.write_image(str(tmp_path / "no-such-dir" / "d.png"), img)
    assert not (tmp_path / "no-such-dir").exists()


def test_msaa_smooths_edges(ball_scene):
    one = penumbra.render(ball_scene, 96, 64, shadow="none", msaa=1)["linear"]
    eight = penumbra.render(ball_scene, 96, 64, shadow="none", msaa=8, threads=1)["linear"]
    again = penumbra.render(ball_scene, 96, 64, shadow="none", msaa=8, threads=3)["linear"]
    assert np.array_equal(eight, again)
    # Partly covered pixels on the silhouette against the sky: alpha strictly between 0 and 1.
    assert set(np.unique(one[..., 3])) <= {0.0, 1.0}
    partial = (eight[..., 3] > 0) & (eight[..., 3] < 1)
    assert partial.sum() > 20
    with pytest.raises(penumbra.Error, match="--msaa"):
        penumbra.render(ball_scene, 16, 16, msaa=3)


def test_concurrent_renders_of_one_lit_scene(ball_scene):
    results, errors = [], []

    def work():
        try:
            results.append(penumbra.render(ball_scene, 120, 80, shadow="pcss")["color"])
        except penumbra.Error as e:
            errors.append(str(e))

    threads = [threading.Thread(target=work) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors and len(results) == 3
    assert all(np.array_equal(results[0], r) for r in results[1:])


def test_camera_checks(ball_scene):
    ball_scene.set_camera(eye=(0, 3, 6), target=(0, 0, 0), near=2.0, far=1.0)
    with pytest.raises(penumbra.Error, match="near and far"):
        penumbra.render(ball_scene, 16, 16)
    ball_scene.set_camera(eye=(0, 3, 6), target=(0, 0, 0), near=float("nan"))
    with pytest.raises(penumbra.Error, match="near and far"):
        penumbra.render(ball_scene, 16, 16)
    # An infinite far plane (the limit of a GL projection) is accepted: far fitted to the scene.
    n, fov = 0.5, np.radians(40.0)
    proj = np.zeros((4, 4))
    proj[0, 0], proj[1, 1] = 1 / np.tan(fov / 2), 1 / np.tan(fov / 2)
    proj[2, 2], proj[2, 3], proj[3, 2] = -1.0, -2 * n, -1
    view = np.eye(4)
    view[2, 3] = -6.0
    ball_scene.set_camera_matrices(view, proj)
    assert (penumbra.render(ball_scene, 32, 32, aov=["instance"])["instance"] >= 0).any()
    bad = view.copy()
    bad[3, 0] = 1.0
    with pytest.raises(penumbra.Error, match="rigid"):
        ball_scene.set_camera_matrices(bad, proj)
