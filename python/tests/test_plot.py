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
