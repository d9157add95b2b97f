#!/usr/bin/python3
"""geostation-batch extract on one and on two workers of a local cluster, in one run.

A simulated aerial strip (9 images, 8 stereo pairs, 0.5 m ground pixel,
4096 x 4096 px by default) is extracted twice from scratch: with --workers 1
(the baseline) and --workers 2. Prints, as JSON: both wall times and their
ratio (aim >= 1.7 on two cores), a unit's median time, what starting
qgis_process costs of it (aim < 10 %) and the largest qgis_process's peak
memory. The plugin is installed into a temporary HOME from BUILD_DIR.

    bench/batch_scaling.py SOURCE_DIR BUILD_DIR [--size PX] [--images N]
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source_dir")
    parser.add_argument("build_dir")
    parser.add_argument("--size", type=int, default=4096, help="image width and height (px)")
    parser.add_argument("--images", type=int, default=9, help="images along the strip (pairs: one fewer)")
    args = parser.parse_args()
    tmp = tempfile.mkdtemp(prefix="geostation-bench-batch-")
    try:
        home = os.path.join(tmp, "home")
        os.makedirs(home)
        env = dict(os.environ, HOME=home, QT_QPA_PLATFORM="offscreen", XDG_RUNTIME_DIR=home)
        subprocess.run([os.path.join(args.source_dir, "scripts", "install-plugin.sh"), "--build-dir", args.build_dir], env=env, check=True,
                       capture_output=True)
        strip = os.path.join(tmp, "strip")
        started = time.time()
        subprocess.run(["qgis_process.bin", "run", "geostation:simulate_survey", "--", "PRESET=aerial_stereo", "STATIONS=%d" % args.images, "GSD=0.5",
                        "SEED=3", "NOISE=4", "IMAGE_WIDTH=%d" % args.size, "IMAGE_HEIGHT=%d" % args.size, "OUTPUT_DIR=" + strip],
                       env=env, check=True, capture_output=True)
        simulated = time.time() - started
        batch = os.path.join(home, ".local", "bin", "geostation-batch")
        result = {"images": args.images, "pairs": args.images - 1, "size_px": args.size, "simulation_s": round(simulated, 1)}
        for workers in (1, 2):
            out = os.path.join(tmp, "w%d" % workers, "roads.gpkg")
            started = time.time()
            done = subprocess.run([batch, "extract", "--block", os.path.join(strip, "block.geostation.json"), "--output", out,
                                   "--workers", str(workers), "--qgis-home", home], env=env, capture_output=True, text=True)
            wall = time.time() - started
            if done.returncode != 0:
                sys.stderr.write(done.stderr)
                return 1
            with open(out + ".work/run-report.json") as f:
                report = json.load(f)
            result["workers_%d" % workers] = {"wall_s": round(wall, 1), "unit_median_s": report["unit_seconds"]["median"],
                                              "start_up_s": report["qgis_process_start_seconds"], "start_up_share": report["start_up_share"],
                                              "peak_rss_mb": report["peak_rss_mb"]}
        result["speed_up_2_over_1"] = round(result["workers_1"]["wall_s"] / result["workers_2"]["wall_s"], 2)
        print(json.dumps(result, indent=1))
        return 0
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
