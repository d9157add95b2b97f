#!/usr/bin/python3
"""End-to-end test of the Multiview in QGIS desktop under xvfb-run: a
simulated highway run (exact orientations, image noise), keyboard
navigation, a click on the true pixel of a pole foot, the proposed matches
accepted, and the feature in the GeoPackage within 3 sigma of the truth;
the kerb traced from one click with the Trace tool, written as one line
on the truth kerb; then the project saved and reopened with the session
restored; and the pole measured again into its layer's edit buffer kept
when QGIS, quitting, asks about the edits and is answered Save.
Screenshots of the Multiview and the Overview are kept as artifacts.

    test_desktop_multiview.py SOURCE_DIR BUILD_DIR ARTIFACT_DIR
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

from osgeo import ogr

import desktop_harness

SOURCE_DIR, BUILD_DIR, ARTIFACT_DIR = sys.argv[1:4]
HERE = os.path.dirname(os.path.abspath(__file__))


def truth_tables(gpkg):
    ds = ogr.Open(gpkg)
    objects = {f["id"]: f.GetGeometryRef().GetPoint() for f in ds.GetLayerByName("objects")}
    pixels = {(f["point_id"], f["image_id"]): (f["col"], f["row"]) for f in ds.GetLayerByName("image_truth")}
    roads = {f["id"]: [f.GetGeometryRef().GetPoint(i) for i in range(f.GetGeometryRef().GetPointCount())] for f in ds.GetLayerByName("roads")}
    return objects, pixels, roads


def across_and_beyond(p, line):
    """Plan distance from a point to the line through a dash's nearest segment, and how far along the dash
    the point lies beyond its ends (0 when between them), metres."""
    best = (float("inf"), float("inf"))
    for a, b in zip(line, line[1:]):
        dx, dy = b[0] - a[0], b[1] - a[1]
        length = (dx * dx + dy * dy) ** 0.5 or 1.0
        along = ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length
        across = abs((p[0] - a[0]) * dy - (p[1] - a[1]) * dx) / length
        best = min(best, (across, max(0.0, -along, along - length)), key=sum)
    return best


class DesktopMultiviewTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="geostation-multiview-")
        env, profiles = desktop_harness.install_plugin(SOURCE_DIR, BUILD_DIR, cls.tmp)
        run_dir = os.path.join(cls.tmp, "run")
        subprocess.run([os.path.join(BUILD_DIR, "core", "geostation-simulate"), "--preset", "highway", "--stations", "8",
                        "--seed", "7", "--noise", "1", "--pose-noise-scale", "0", "--output-dir", run_dir, "--quiet"],
                       check=True, capture_output=True)
        objects, pixels, roads = truth_tables(os.path.join(run_dir, "truth.gpkg"))
        with open(os.path.join(run_dir, "block.geostation.json")) as f:
            block = json.load(f)
        stations = sorted({s["id"]: s["time"] for s in block["stations"]}.items(), key=lambda s: s[1])
        # a pole foot seen in both front images, 12-30 m ahead, not at the first station
        cls.click = None
        for index, (station, _) in enumerate(stations[1:], start=1):
            left, right = station + "_FL", station + "_FR"
            for pid, point in sorted(objects.items()):
                if not pid.startswith("pole_") or (pid, left) not in pixels or (pid, right) not in pixels:
                    continue
                centre = next(i for i in block["images"] if i["id"] == left)
                distance = ((point[0] - centre["X"]) ** 2 + (point[1] - centre["Y"]) ** 2) ** 0.5
                if 12 < distance < 30:
                    cls.click = {"station_index": index, "station": station, "image": left, "pole": pid,
                                 "col": pixels[(pid, left)][0], "row": pixels[(pid, left)][1], "truth": point}
                    break
            if cls.click:
                break
        assert cls.click, "the simulated run has no pole to measure"
        # the kerb face (asphalt / kerb) 8-15 m ahead in the same image, well inside both front images
        cls.kerb = [p for rid, line in sorted(roads.items()) if rid.startswith("R1-edge-right-") for p in line]
        centre = next(i for i in block["images"] if i["id"] == cls.click["image"])
        right = cls.click["image"][:-3] + "_FR"
        cls.trace = None
        for (pid, image), (col, row) in sorted(pixels.items()):
            if image != cls.click["image"] or not pid.startswith("R1-edge-right-") or (pid, right) not in pixels:
                continue
            rid, index = pid.rsplit(":", 1)
            point = roads[rid][int(index)]
            distance = ((point[0] - centre["X"]) ** 2 + (point[1] - centre["Y"]) ** 2) ** 0.5
            rcol, rrow = pixels[(pid, right)]
            if 8 < distance < 15 and min(col, row, rcol, rrow) > 40 and max(col, rcol) < 600 and max(row, rrow) < 440:
                cls.trace = {"col": col + 0.8, "row": row - 0.6, "point": pid}
                break
        assert cls.trace, "the kerb is not in view of both front images"
        # the middle of a dash of the lane line (R1-separator3, 3 m dashes), 6-20 m ahead of the first station,
        # inside both front images
        cls.lane_truth = {rid: line for rid, line in roads.items() if rid.startswith("R1-separator3-")}
        cls.lane = None
        first = stations[0][0]
        centre = next(i for i in block["images"] if i["id"] == first + "_FL")
        for rid, line in sorted(cls.lane_truth.items()):
            key = "%s:%d" % (rid, len(line) // 2)
            if (key, first + "_FL") not in pixels or (key, first + "_FR") not in pixels:
                continue
            point = line[len(line) // 2]
            (col, row), (rcol, rrow) = pixels[(key, first + "_FL")], pixels[(key, first + "_FR")]
            distance = ((point[0] - centre["X"]) ** 2 + (point[1] - centre["Y"]) ** 2) ** 0.5
            if 6 < distance < 20 and min(col, row, rcol, rrow) > 40 and max(col, rcol) < 600 and max(row, rrow) < 440:
                cls.lane = {"col": col + 0.6, "row": row + 0.7, "point": key}
                break
        assert cls.lane, "no dash of the lane line in view of both front images"

        os.makedirs(ARTIFACT_DIR, exist_ok=True)
        cls.target = os.path.join(cls.tmp, "measurements.gpkg")
        cls.project = os.path.join(cls.tmp, "session.qgz")
        result_path = os.path.join(cls.tmp, "result.json")
        env.update(GEOSTATION_E2E_RESULT=result_path, GEOSTATION_E2E_ARTIFACTS=ARTIFACT_DIR,
                   GEOSTATION_E2E_BLOCK=os.path.join(run_dir, "block.geostation.json"),
                   GEOSTATION_E2E_TARGET=cls.target, GEOSTATION_E2E_PROJECT=cls.project,
                   GEOSTATION_E2E_CLICK=json.dumps(cls.click), GEOSTATION_E2E_TRACE=json.dumps(cls.trace), GEOSTATION_E2E_LANE=json.dumps(cls.lane))
        cls.exit_code, cls.log = desktop_harness.run_qgis(os.path.join(HERE, "desktop_multiview_script.py"), env, profiles,
                                                          screen="1600x1000")
        cls.result = {}
        if os.path.exists(result_path):
            with open(result_path) as f:
                cls.result = json.load(f)
        print(json.dumps({k: cls.result.get(k) for k in ("navigation_ms", "proposal_ms", "features", "clicked_pixel", "trace_seconds", "trace_status", "lane_status")}, indent=1))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_qgis_ran_the_script(self):
        self.assertTrue(self.result, "the script inside QGIS wrote nothing:\n" + self.log)
        self.assertNotIn("exception", self.result, self.result.get("exception"))
        self.assertEqual(self.exit_code, 0, self.log)

    def test_quitting_with_edits_asks_once_and_saving_keeps_the_feature(self):
        # the pole measured with its layer in editing waits in the edit buffer, not yet on disk
        self.assertTrue(self.result.get("pole_editing"))
        self.assertEqual(self.result.get("buffered_features"), 1, [self.result.get(k) for k in ("buffer_station", "buffer_messages", "pole_layers", "poles_on_disk_before_exit", "exit_dialogs")])
        self.assertEqual(self.result.get("poles_on_disk_before_exit"), 1)
        # QGIS asks once, about that layer, and nothing else; answered Save, both poles and their vertex rows are on disk
        dialogs = self.result.get("exit_dialogs", [])
        self.assertEqual(len(dialogs), 1, dialogs)
        self.assertIn("pole", dialogs[0])
        ds = ogr.Open(self.target)
        poles = list(ds.GetLayerByName("pole"))
        self.assertEqual(len(poles), 2)
        vertex_rows = [f for f in ds.GetLayerByName("vertices") if f["layer"] == "pole"]
        self.assertEqual(len(vertex_rows), 2)
        self.assertEqual(sorted(f["feature_fid"] for f in vertex_rows), sorted(f.GetFID() for f in poles))

    def test_block_opens_with_overview_layers(self):
        self.assertTrue(self.result.get("block_opened"))
        self.assertTrue(self.result.get("classes_set"))
        self.assertTrue(self.result.get("target_set"))
        self.assertTrue(self.result.get("dock"))
        for name in ("Trajectory", "Stations", "View cones"):
            self.assertIn(name, self.result.get("overview_layers", []))

    def test_keyboard_navigation(self):
        self.assertIn("8 of 8", self.result.get("after_end", ""))
        state = self.result.get("at_station", {})
        self.assertIn("station " + self.click["station"], state.get("title", ""))
        layers = [v["layers"] for v in state.get("views", [])]
        self.assertEqual(layers, [[self.click["station"] + s] for s in ("_FL", "_FR", "_SR")])
        self.assertEqual(len(self.result.get("navigation_ms", [])), self.click["station_index"])

    def test_click_proposes_the_conjugate_point(self):
        clicked = self.result.get("clicked_pixel")
        self.assertLess(abs(clicked[0] - self.click["col"]) + abs(clicked[1] - self.click["row"]), 0.3)
        views = self.result.get("after_click", {}).get("views", [])
        self.assertIn("reference", views[0]["status"])
        self.assertIn("match", views[1]["status"])

    def test_measured_pole_foot_is_within_three_sigma_of_the_truth(self):
        features = self.result.get("features", [])
        self.assertEqual(len(features), 1, self.result.get("messages"))
        f = features[0]
        self.assertEqual(f["class"], "Pole")
        self.assertEqual(f["method"], "intersection")
        self.assertEqual(f["station"], self.click["station"])
        self.assertGreaterEqual(f["n_images"], 2)
        truth = self.click["truth"]
        for axis, measured, sigma, true in zip("xyz", (f["x"], f["y"], f["z"]), f["sigma"], truth):
            self.assertLess(abs(measured - true), 3 * sigma, "%s: %.3f m off, sigma %.3f m" % (axis, measured - true, sigma))
        self.assertIn("Vertex 1 (intersection", self.result.get("messages", ""))

    def test_trace_tool_writes_the_kerb_from_one_click(self):
        traced = self.result.get("traced", [])
        self.assertEqual(len(traced), 1, self.result.get("trace_messages"))
        line = traced[0]
        self.assertEqual(line["method"], "traced")
        self.assertEqual(line["class"], "Road edge")
        self.assertIn("end_of_run", self.result.get("trace_status", ""))
        self.assertGreaterEqual(len(line["vertices"]), 10)
        self.assertEqual(self.result.get("traced_vertex_rows"), len(line["vertices"]))
        # on the truth kerb (exact orientation): 95 % of the vertices within 0.10 m
        errors = [desktop_harness.distance_to_polyline(v, self.kerb) for v in line["vertices"]]
        plan = sorted(e[0] for e in errors)
        height = sorted(abs(e[1]) for e in errors)
        self.assertLess(plan[int(0.95 * (len(plan) - 1))], 0.10, plan)
        self.assertLess(height[int(0.95 * (len(height) - 1))], 0.10, height)

    def test_trace_tool_writes_the_dashed_lane_line_from_one_click(self):
        lanes = self.result.get("lane", [])
        self.assertEqual(len(lanes), 1, self.result.get("lane_messages"))
        self.assertEqual(lanes[0]["method"], "traced")
        self.assertIn("end_of_run", self.result.get("lane_status", ""))
        vertices = lanes[0]["vertices"]
        self.assertGreaterEqual(len(vertices), 6)
        # every vertex on a dash of the lane line (exact orientation: within 0.10 m of the dash's line across it).
        # Along the line a dash's end is placed to a pixel or so: at 20 m in these 640 px images a pixel covers
        # about 0.3 m of road along the line, so a vertex may stop that far beyond a dash's painted end.
        dashes = list(self.lane_truth.values())
        placed = sorted(min((across_and_beyond(v, d) for d in dashes), key=sum) for v in vertices)
        for across, beyond in placed:
            self.assertLess(across, 0.10, placed)
            self.assertLess(beyond, 0.30, placed)

    def test_session_is_restored_from_the_project(self):
        self.assertTrue(self.result.get("saved"))
        self.assertTrue(self.result.get("reopened"))
        self.assertEqual(self.result.get("restored_title"), self.result.get("saved_title"))
        for name in ("Trajectory", "Stations", "View cones", "pole"):
            self.assertIn(name, self.result.get("restored_layers", []))

    def test_screenshots_saved(self):
        for name in ("multiview-traced.png", "multiview-traced-lane.png", "overview-traced.png", "multiview-proposals.png", "multiview-measured.png", "overview.png"):
            path = os.path.join(ARTIFACT_DIR, name)
            self.assertTrue(os.path.exists(path), name)
            self.assertGreater(os.path.getsize(path), 10000)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
