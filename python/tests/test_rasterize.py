"""penumbra.rasterize: the bare pipeline against the scalar reference, watertight, exact."""
import numpy as np
import pytest

import penumbra


def random_triangles(rng, n):
    xy = rng.uniform(-1.2, 1.2, size=(n, 3, 2))
    z = rng.uniform(0.05, 0.95, size=(n, 3, 1))
    w = rng.uniform(0.5, 2.0, size=(n, 3, 1))
    return np.concatenate([xy * w, z * w, w], axis=2).astype(np.float32)


def test_coverage_equals_the_reference():
    rng = np.random.default_rng(7)
    for tri in random_triangles(rng, 60):
        for size in ((37, 23), (64, 64)):
            out = penumbra.rasterize(tri, np.array([[0, 1, 2]]), *size)
            ref = penumbra.reference_coverage(tri, *size)
            assert np.array_equal(out["triangle"] == 0, ref == 1)


def test_a_closed_fan_covers_every_pixel_once():
    # 40 triangles around an off-centre point: inside the polygon every pixel centre is covered
    # by exactly one triangle (the top-left rule), checked triangle by triangle.
    k = 40
    a = np.linspace(0, 2 * np.pi, k, endpoint=False) + 0.1
    rim = np.stack([0.9 * np.cos(a), 0.85 * np.sin(a)], axis=1)
    centre = np.array([[0.137, -0.071]])
    v = np.concatenate([centre, rim])
    clip = np.concatenate([v, np.full((k + 1, 1), 0.5), np.ones((k + 1, 1))], axis=1).astype(np.float32)
    tris = np.array([[0, 1 + i, 1 + (i + 1) % k] for i in range(k)])
    count = np.zeros((97, 101), dtype=int)
    for t in tris:
        count += penumbra.rasterize(clip, t[None, :], 101, 97)["triangle"] == 0
    assert count.max() == 1
    whole = penumbra.rasterize(clip, tris, 101, 97)
    assert np.array_equal(whole["triangle"] >= 0, count == 1)
    assert (count == 1).sum() > 0.5 * 101 * 97


def test_barycentrics_are_perspective_correct():
    rng = np.random.default_rng(3)
    clip = random_triangles(rng, 1)[0]
    w, h = 80, 60
    out = penumbra.rasterize(clip, np.array([[0, 1, 2]]), w, h)
    ys, xs = np.nonzero(out["triangle"] == 0)
    assert len(xs) > 20
    b = out["barycentrics"][ys, xs]
    p = b @ clip.astype(np.float64)  # the clip position at the pixel centre
    ndc_x, ndc_y = p[:, 0] / p[:, 3], p[:, 1] / p[:, 3]
    # Pixel centres in NDC, y up (row 0 at the top).
    assert np.allclose(ndc_x, (xs + 0.5) / w * 2 - 1, atol=2e-3)
    assert np.allclose(ndc_y, 1 - (ys + 0.5) / h * 2, atol=2e-3)
    assert np.allclose(out["depth"][ys, xs], p[:, 2] / p[:, 3], atol=1e-4)


def test_nearest_wins_and_threads_agree():
    rng = np.random.default_rng(11)
    tris = random_triangles(rng, 300)
    clip = tris.reshape(-1, 4)
    idx = np.arange(len(clip)).reshape(-1, 3)
    runs = [penumbra.rasterize(clip, idx, 128, 96, threads=t) for t in (1, 2, 4)]
    for r in runs[1:]:
        for k in ("triangle", "depth", "barycentrics", "front_facing"):
            assert np.array_equal(runs[0][k], r[k], equal_nan=True)
    # Every covered pixel shows the nearest covering triangle.
    out = runs[0]
    for t in rng.choice(len(idx), 25, replace=False):
        mine = penumbra.rasterize(clip, idx[t][None, :], 128, 96)
        covered = mine["triangle"] == 0
        assert (out["depth"][covered] <= mine["depth"][covered]).all()


def test_culling_and_stats():
    ccw = np.array([[-0.5, -0.5, 0.5, 1], [0.5, -0.5, 0.5, 1], [0, 0.5, 0.5, 1]], dtype=np.float32)
    out = penumbra.rasterize(ccw, np.array([[0, 1, 2]]), 32, 32, cull="none")
    assert out["stats"]["triangles"] == 1 and (out["triangle"] == 0).sum() > 50
    front = out["front_facing"][out["triangle"] == 0]
    assert front.all() or not front.any()
    culled = penumbra.rasterize(ccw, np.array([[0, 1, 2]]), 32, 32, cull="front" if front.all() else "back")
    assert (culled["triangle"] == -1).all() and culled["stats"]["culled_facing"] == 1
    behind = ccw.copy()
    behind[:, 3] = -1
    assert (penumbra.rasterize(behind, np.array([[0, 1, 2]]), 32, 32)["triangle"] == -1).all()


@pytest.mark.parametrize(
    "vertices, triangles, kwargs, match",
    [
        (np.zeros((3, 3)), [[0, 1, 2]], {}, r"vertices_clip: expected shape \(N, 4\)"),
        (np.full((3, 4), np.nan), [[0, 1, 2]], {}, "vertices_clip: row 0 is not finite"),
        (np.ones((3, 4)), [[0, 1, 3]], {}, "index 3, out of range"),
        (np.ones((3, 4)), [[0, 1, 2]], {"width": 0}, "width"),
        (np.ones((3, 4)), [[0, 1, 2]], {"cull": "sideways"}, "cull"),
        (np.ones((3, 4)), [[0.0, 1.0, 2.0]], {}, "integer indices"),
    ],
)
def test_bad_rasterize_input(vertices, triangles, kwargs, match):
    args = {"width": 16, "height": 16, **kwargs}
    with pytest.raises(penumbra.Error, match=match):
        penumbra.rasterize(np.asarray(vertices), np.asarray(triangles), **args)
