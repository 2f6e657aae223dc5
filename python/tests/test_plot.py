"""`python3 -m rayaccel.plot`: figures from real `rayaccel bench --json` output, and clear errors for bad files."""
import json
import subprocess
import sys

import pytest

pytest.importorskip("matplotlib", reason="python3-matplotlib (scripts/setup.sh) draws the plots")
from rayaccel import plot  # noqa: E402


def test_plots_of_a_bench_run(cli, tmp_path):
    bench = tmp_path / "bench.json"
    run = subprocess.run([cli, "bench", "builtin:sphere:level=2", "builtin:soup:count=500", "--accel",
                          "bvh_wide,grid", "--compare", "embree", "--res", "24", "--repeat", "1", "--json", str(bench)],
                         capture_output=True, text=True, timeout=120)
    if run.returncode != 0 and "embree" in run.stderr.lower():  # a build without Embree: no ratio plots
        run = subprocess.run([cli, "bench", "builtin:sphere:level=2", "--accel", "bvh_wide,grid", "--res", "24",
                              "--repeat", "1", "--json", str(bench)], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    out = tmp_path / "plots"
    done = subprocess.run([sys.executable, "-m", "rayaccel.plot", str(bench), "--out", str(out)],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    written = done.stdout.split()
    scenes = json.loads(bench.read_text())["scenes"]
    with_embree = any(r["is_embree"] for s in scenes for r in s["results"])
    assert len(written) == len(scenes) * (3 if with_embree else 2)
    for path in written:
        assert open(path, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
    assert any("sphere-t" in p and p.endswith("-mrays.png") for p in written)


def test_bad_bench_files(tmp_path, capsys):
    with pytest.raises(SystemExit) as missing:
        plot.main([str(tmp_path / "none.json"), "--out", str(tmp_path)])
    assert missing.value.code == 2 and "does not exist" in capsys.readouterr().err
    (tmp_path / "bad.json").write_text("{not json")
    with pytest.raises(SystemExit):
        plot.main([str(tmp_path / "bad.json"), "--out", str(tmp_path)])
    assert "is not JSON" in capsys.readouterr().err
    (tmp_path / "other.json").write_text('{"x": 1}')
    with pytest.raises(SystemExit):
        plot.main([str(tmp_path / "other.json"), "--out", str(tmp_path)])
    assert "no 'scenes' list" in capsys.readouterr().err


def _many_structures():
    """A bench file's worth of rows like `--accel all --compare embree` gives: 60 structures and Embree."""
    kinds = ["primary", "diffuse", "shadow", "occlusion", "light", "packet", "light_packet"]
    specs = ["embree", "brute_force", "bvh_wide"] + [f"bvh:bv=obb,leaf={i}" for i in range(30)] + \
        [f"kdtree:leaf={i}" for i in range(14)] + [f"grid:density={i}" for i in range(14)]
    rows = []
    for i, spec in enumerate(specs):
        speed = 0.002 if spec == "brute_force" else 5.0 + i % 7
        rows.append({"accel": spec, "is_embree": spec == "embree", "build_ms_median": 10.0 + i,
                     "memory_bytes": (1 + i % 5) << 20, "input_memory_bytes": 1 << 20,
                     "rays": {k: {"mrays_s_median": speed} for k in kinds}})
    return {"threads": 2, "default_accel": "bvh_wide",
            "scenes": [{"scene": "many", "primitives": 1000, "kind": "triangles", "resolution": 64, "results": rows}]}


def test_many_structures_make_compact_figures(tmp_path):
    """One panel per ray kind, a figure a screen can show, and no wide blank margins (bbox tight)."""
    from matplotlib import image

    bench = tmp_path / "many.json"
    bench.write_text(json.dumps(_many_structures()))
    out = tmp_path / "plots"
    assert plot.main([str(bench), "--out", str(out)]) == 0
    for name in ("many-t2-mrays.png", "many-t2-vs-embree.png", "many-t2-build-memory.png"):
        pixels = image.imread(out / name)
        height, width = pixels.shape[:2]
        assert width <= 2000 and height <= 1600, (name, width, height)
        ink = (pixels[:, :, :3] < 0.95).any(axis=2)
        rows, cols = ink.any(axis=1).nonzero()[0], ink.any(axis=0).nonzero()[0]
        margins = (rows[0], height - 1 - rows[-1], cols[0], width - 1 - cols[-1])
        assert max(margins) <= 20, (name, margins)


def test_ratio_axes_leave_out_brute_force_and_group_families():
    scene = _many_structures()["scenes"][0]
    rows = plot.grouped(scene["results"], "bvh_wide")
    families = [plot.family(row, "bvh_wide") for row in rows]
    assert families[:2] == ["embree", "default"]
    assert families == sorted(families, key=lambda f: plot.FAMILIES[f][0]), "each family together"
    embree, others = plot.ratio_rows(rows, "bvh_wide")
    assert embree["accel"] == "embree"
    assert "brute_force" not in [row["accel"] for row in others]
    assert len(others) == len(rows) - 2


def test_scatter_labels_never_overlap():
    plt = plot._pyplot()
    fig, ax = plt.subplots(figsize=(4, 3))
    points = [(1.0 + 0.01 * i, 1.0 + 0.01 * i, f"structure {i}") for i in range(40)]
    ax.scatter([p[0] for p in points], [p[1] for p in points])
    ax.set_xlim(0.5, 2.0)
    ax.set_ylim(0.5, 2.0)
    placed = plot._place_labels(fig, ax, points)
    renderer = fig.canvas.get_renderer()
    boxes = [label.get_window_extent(renderer) for label in placed]
    assert 1 <= len(boxes) < len(points)
    assert placed[0].get_text() == "structure 0", "the first point has priority"
    for i, a in enumerate(boxes):
        for b in boxes[i + 1:]:
            assert not a.overlaps(b)
    plt.close(fig)
