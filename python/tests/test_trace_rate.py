"""bench/python/trace_rate.py runs (a small DEM, few rays): both sides hit the same rays and the
table has a rate and ratio per thread count."""

import os
import re
import subprocess
import sys

from conftest import REPO


def test_trace_rate_script_on_a_small_dem(shared_data, tmp_path):
    dem = shared_data / "meshes" / "terrain" / "dem_hd_sub.tif"
    scene = tmp_path / "dem.yaml"
    scene.write_text(f"materials:\n  - {{name: ground, reflectance: 0.3}}\nparts:\n"
                     f"  - {{name: terrain, raster: {dem}, material: ground, label: 2}}\n")
    run = subprocess.run([sys.executable, str(REPO / "bench" / "python" / "trace_rate.py"),
                          "--scene", str(scene), "--rays", "20000", "--threads", "1", "2",
                          "--repeats", "1"], capture_output=True, text=True, env=os.environ)
    assert run.returncode == 0, run.stderr
    hit = re.search(r"20000 rays \((\d+) hit\)", run.stdout)  # the same count on both sides
    assert hit and int(hit.group(1)) > 19000, run.stdout
    rows = re.findall(r"^\| (\d+)[^|]*\| ([\d.]+) \| ([\d.]+) \| ([\d.]+) \| ([\d.]+) "
                      r"\| ([\d.]+) \|$", run.stdout, re.M)
    assert [r[0] for r in rows] == ["1", "2"], run.stdout
    for _, py_rate, cpp_rate, ratio, median, cpu_ratio in rows:
        assert float(py_rate) > 0 and float(cpp_rate) > 0 and float(median) > 0
        assert float(cpu_ratio) > 0
        assert median == ratio  # one round (--repeats 1): its ratio is the median
        assert abs(float(ratio) - float(py_rate) / float(cpp_rate)) < 0.05 * float(ratio) + 0.01
