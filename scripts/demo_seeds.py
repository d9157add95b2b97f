#!/usr/bin/python3
"""Writes the demo's tracing seeds: where an operator would click on the
dashed lane line and on the kerb in one image of the simulated highway run
(a truth vertex 6-20 m ahead, on paint, seen well inside the image and its
stereo partner), as the SEEDS table of geostation:trace_road_lines.

    demo_seeds.py RUN_DIR IMAGE_ID PARTNER_ID OUT_CSV
"""

import csv
import json
import math
import os
import sys

from osgeo import ogr

LINES = [("lane_dashed", "R1-separator3-"), ("kerb", "R1-edge-right-")]


def main(run_dir, image_id, partner_id, out_csv):
    ds = ogr.Open(os.path.join(run_dir, "truth.gpkg"))
    if ds is None:
        sys.exit("demo_seeds.py: cannot read " + os.path.join(run_dir, "truth.gpkg"))
    pixels = {(f["point_id"], f["image_id"]): (f["col"], f["row"]) for f in ds.GetLayerByName("image_truth")}
    roads = {f["id"]: [f.GetGeometryRef().GetPoint(i) for i in range(f.GetGeometryRef().GetPointCount())] for f in ds.GetLayerByName("roads")}
    with open(os.path.join(run_dir, "block.geostation.json")) as f:
        block = json.load(f)
    image = next(i for i in block["images"] if i["id"] == image_id)
    camera = next(c for c in block["cameras"] if c["id"] == image["camera"])
    width, height = camera["width"], camera["height"]
    rows = []
    for seed_id, prefix in LINES:
        for road_id in sorted(r for r in roads if r.startswith(prefix)):
            line = roads[road_id]
            # a dash's middle is on paint; a continuous line's inner vertices
            indices = [len(line) // 2] if len(line) <= 3 else range(1, len(line) - 1)
            seed = None
            for index in indices:
                point = line[index]
                key = "%s:%d" % (road_id, index)
                if (key, image_id) not in pixels or (key, partner_id) not in pixels:
                    continue
                (col, row), (pcol, prow) = pixels[(key, image_id)], pixels[(key, partner_id)]
                distance = math.hypot(point[0] - image["X"], point[1] - image["Y"])
                margin = 40
                if 6 <= distance <= 20 and min(col, row, pcol, prow) > margin and max(col, pcol) < width - margin and max(row, prow) < height - margin:
                    seed = {"seed_id": seed_id, "image_id": image_id, "col": "%.1f" % col, "row": "%.1f" % row}
                    break
            if seed:
                rows.append(seed)
                break
        else:
            sys.exit("demo_seeds.py: the %s line is not in view of %s and %s" % (seed_id, image_id, partner_id))
    with open(out_csv, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=["seed_id", "image_id", "col", "row"])
        writer.writeheader()
        writer.writerows(rows)


if __name__ == "__main__":
    if len(sys.argv) != 5:
        sys.exit(__doc__)
    main(*sys.argv[1:])
