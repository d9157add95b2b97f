#!/usr/bin/python3
"""End-to-end test of orienting a single photo in QGIS desktop under
xvfb-run, as a new user does it: the simulator's scanned oblique photo is
added with GeoStation > Add Photo (a new block; the film camera's
calibration typed in), its fiducials detected, the control layer loaded,
four control points clicked in the photo (real mouse clicks on the
Multiview), the rest found by the semi-automatic mode and accepted, the
orientation saved into the block; then a road centre line digitised in the
photo (five clicks, each monoplotted on the DEM layer) lands in the
GeoPackage on the true road. Screenshots are kept as artifacts.

    test_desktop_orientation.py SOURCE_DIR BUILD_DIR ARTIFACT_DIR
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

from osgeo import gdal, ogr

import desktop_harness

SOURCE_DIR, BUILD_DIR, ARTIFACT_DIR = sys.argv[1:4]
HERE = os.path.dirname(os.path.abspath(__file__))


class DesktopOrientationTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="geostation-orientation-")
        env, profiles = desktop_harness.install_plugin(SOURCE_DIR, BUILD_DIR, cls.tmp)
        sim = os.path.join(cls.tmp, "sim")
        subprocess.run([os.path.join(BUILD_DIR, "core", "geostation-simulate"), "--preset", "oblique_photo", "--scanned-film", "1",
                        "--seed", "5", "--noise", "2", "--output-dir", sim, "--quiet"], check=True, capture_output=True)
        with open(os.path.join(sim, "block.geostation.json")) as f:
            block = json.load(f)
        with open(os.path.join(sim, "truth.geostation.json")) as f:
            cls.truth_block = json.load(f)
        camera = block["cameras"][0]
        image = block["images"][0]
        # the user's copy of the photo, in a folder of its own: nothing of the simulation's block comes along
        work = os.path.join(cls.tmp, "work")
        os.makedirs(work)
        cls.photo = os.path.join(work, "oblique_1962.tif")
        shutil.copy(os.path.join(sim, image["path"]), cls.photo)
        cls.camera = {k: camera[k] for k in ("id", "width", "height", "f", "cx", "cy", "pixel_size_mm", "fiducials", "distortion") if k in camera}

        ds = ogr.Open(os.path.join(sim, "truth.gpkg"))
        control = {f["id"]: f.GetGeometryRef().GetPoint() for f in ds.GetLayerByName("control")}
        pixels = {(f["point_id"], f["image_id"]): (f["col"], f["row"]) for f in ds.GetLayerByName("image_truth")}
        cls.roads = {f["id"]: [f.GetGeometryRef().GetPoint(i) for i in range(f.GetGeometryRef().GetPointCount())] for f in ds.GetLayerByName("roads")}
        ds = None
        width, height = camera["width"], camera["height"]
        visible = sorted((pixels[(pid, image["id"])][0], pid) for pid in control if (pid, image["id"]) in pixels)
        assert len(visible) >= 8, "too few control points in the photo"
        picks = [visible[0], visible[len(visible) // 3], visible[2 * len(visible) // 3], visible[-1]]
        cls.clicks = [{"id": pid, "col": pixels[(pid, image["id"])][0], "row": pixels[(pid, image["id"])][1]} for _, pid in picks]
        # five vertices of the road's centre line in the photo, well inside the frame, spread along it
        centre = [(int(k.split(":")[1]), v) for (k, img), v in pixels.items() if img == image["id"] and k.startswith("R1-centre-001:")]
        centre = sorted((i, v) for i, v in centre if 60 < v[0] < width - 60 and 60 < v[1] < height - 60)
        assert len(centre) >= 20, "the road is not in view"
        step = (len(centre) - 1) // 4
        cls.road_clicks = [{"col": centre[k * step][1][0], "row": centre[k * step][1][1], "vertex": centre[k * step][0]} for k in range(5)]

        cls.dem_path = os.path.join(sim, "terrain.tif")
        os.makedirs(ARTIFACT_DIR, exist_ok=True)
        result_path = os.path.join(cls.tmp, "result.json")
        cls.block_path = os.path.join(work, "oblique_1962.geostation.json")
        cls.target = os.path.join(work, "roads.gpkg")
        env.update(GEOSTATION_E2E_RESULT=result_path, GEOSTATION_E2E_ARTIFACTS=ARTIFACT_DIR, GEOSTATION_E2E_PHOTO=cls.photo,
                   GEOSTATION_E2E_BLOCK=cls.block_path, GEOSTATION_E2E_CAMERA=json.dumps(cls.camera), GEOSTATION_E2E_CRS=block["crs"],
                   GEOSTATION_E2E_DEM=os.path.join(sim, "terrain.tif"), GEOSTATION_E2E_CONTROL=os.path.join(sim, "truth.gpkg") + "|layername=control",
                   GEOSTATION_E2E_CLICKS=json.dumps(cls.clicks), GEOSTATION_E2E_ROAD=json.dumps(cls.road_clicks), GEOSTATION_E2E_TARGET=cls.target)
        cls.exit_code, cls.log = desktop_harness.run_qgis(os.path.join(HERE, "desktop_orientation_script.py"), env, profiles, screen="1600x1000")
        cls.result = {}
        if os.path.exists(result_path):
            with open(result_path) as f:
                cls.result = json.load(f)
        print(json.dumps({k: cls.result.get(k) for k in ("image_id", "fiducials", "after_clicks", "offers", "after_accept", "saved", "road")}, indent=1))

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_qgis_ran_the_script(self):
        self.assertTrue(self.result, "the script inside QGIS wrote nothing:\n" + self.log)
        self.assertNotIn("exception", self.result, self.result.get("exception"))
        self.assertEqual(self.exit_code, 0, self.log)
        self.assertEqual(self.result.get("exit_dialogs", []), [])

    def test_photo_added_to_a_new_block_unoriented(self):
        self.assertEqual(self.result.get("image_id"), "oblique_1962")
        self.assertTrue(self.result.get("orientation_dock"))
        self.assertEqual(self.result.get("view_image"), "oblique_1962")
        self.assertIn("not oriented", self.result.get("photo_choice", ""))

    def test_fiducials_detected_with_the_affine_decomposition(self):
        text = self.result.get("fiducials", "")
        for word in ("A ", "B ", "α_A", "affinity", "β", "σ0"):
            self.assertIn(word, text)

    def test_four_clicks_orient_and_the_rest_are_found(self):
        self.assertIn("Oriented from 4 control points", self.result.get("after_clicks", ""))
        self.assertGreaterEqual(self.result.get("offers_found", 0), 5, self.result.get("offers"))
        found = self.result.get("offers_found", 0)
        self.assertIn("Oriented from %d control points" % (4 + found), self.result.get("after_accept", ""))
        self.assertEqual(self.result.get("measured_after_accept", 0), 4 + found)

    def test_saved_orientation_is_near_the_truth(self):
        self.assertTrue(self.result.get("saved"), self.result.get("save_message"))
        # the dock reads the saved block back: the photo is listed as oriented, with its inner orientation
        self.assertEqual(self.result.get("photo_choice_saved"), "oblique_1962")
        self.assertIn("scanned film (pixels of the scan", self.result.get("camera_line_saved", ""))
        self.assertIn("; oriented", self.result.get("camera_line_saved", ""))
        with open(self.block_path) as f:
            block = json.load(f)
        image = block["images"][0]
        true_image = self.truth_block["images"][0]
        self.assertIn("inner_orientation", image)
        error = sum((image[k] - true_image[k]) ** 2 for k in ("X", "Y", "Z")) ** 0.5
        print("saved camera %.3f m from the truth" % error)
        self.assertLess(error, 1.0, "camera %.2f m from the truth" % error)
        self.assertTrue(os.path.exists(os.path.join(os.path.dirname(self.block_path), "oblique_1962.oblique_1962.control.csv")))

    def test_digitised_road_lies_on_the_true_road(self):
        roads = self.result.get("road", [])
        self.assertEqual(len(roads), 1, self.result.get("road_messages"))
        vertices = roads[0]["vertices"]
        self.assertEqual(roads[0]["method"], "monoplot-DEM")
        # the five clicks, and between them the line densified on the terrain (a vertex every 20 px of the photo)
        self.assertGreater(len(vertices), 5 + 4, self.result.get("road_messages"))
        self.assertEqual(len(roads[0]["sigmas"]), len(vertices))
        line = self.roads["R1-centre-001"]
        for click in self.road_clicks:
            truth = line[click["vertex"]]
            k = min(range(len(vertices)), key=lambda i: (vertices[i][0] - truth[0]) ** 2 + (vertices[i][1] - truth[1]) ** 2)
            v, sigma = vertices[k], roads[0]["sigmas"][k]
            plan = ((v[0] - truth[0]) ** 2 + (v[1] - truth[1]) ** 2) ** 0.5
            print("clicked road vertex: %.3f m from the truth in plan, %.3f m in height; sigma %.3f / %.3f / %.3f m" % (plan, v[2] - truth[2], *sigma))
            self.assertLess(plan, max(3 * (sigma[0] ** 2 + sigma[1] ** 2) ** 0.5, 0.15), "vertex %s: %.2f m off the road" % (v, plan))
            self.assertLess(abs(v[2] - truth[2]), max(3 * sigma[2], 0.15))
        # every vertex on the terrain
        dem = gdal.Open(self.dem_path)
        gt = dem.GetGeoTransform()
        band = dem.GetRasterBand(1)
        worst = 0.0
        for v in vertices:
            col, row = (v[0] - gt[0]) / gt[1] - 0.5, (v[1] - gt[3]) / gt[5] - 0.5
            c0, r0 = int(col), int(row)
            cells = band.ReadAsArray(c0, r0, 2, 2).astype(float)
            fc, fr = col - c0, row - r0
            z = (cells[0][0] * (1 - fc) + cells[0][1] * fc) * (1 - fr) + (cells[1][0] * (1 - fc) + cells[1][1] * fc) * fr
            worst = max(worst, abs(v[2] - z))
        print("%d vertices, at most %.3f m off the terrain" % (len(vertices), worst))
        self.assertLess(worst, 0.05)

    def test_screenshots_saved(self):
        for name in ("orientation-clicked.png", "orientation-accepted.png", "orientation-map-layer.png", "orientation-road.png"):
            path = os.path.join(ARTIFACT_DIR, name)
            self.assertTrue(os.path.exists(path), name)
            self.assertGreater(os.path.getsize(path), 10000)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
