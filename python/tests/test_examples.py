"""The examples in examples/ run and write what they say."""
import os
import pathlib
import subprocess
import sys

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"


def run(script, *args):
    return subprocess.run([sys.executable, str(EXAMPLES / script), *map(str, args)], check=True,
                          capture_output=True, text=True, env=os.environ.copy()).stdout


def test_mesh_from_numpy(tmp_path):
    out = run("mesh_from_numpy.py", tmp_path)
    assert "instance 0:" in out and "instance 2:" in out
    for name in ("mesh.png", "mesh-triangles.png"):
        data = (tmp_path / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 1000


def test_compare_shadows(tmp_path):
    out = run("compare_shadows.py", "contact", tmp_path)
    lines = [line.split() for line in out.splitlines()]
    rows = {r[0]: r for r in lines if len(r) == 4 and r[0] in ("mvr", "pcss", "hard")}
    assert set(rows) == {"mvr", "pcss", "hard"}
    assert float(rows["mvr"][2]) < float(rows["hard"][2])  # RMSE: soft beats hard
    assert any(p.suffix == ".png" for p in tmp_path.iterdir())
