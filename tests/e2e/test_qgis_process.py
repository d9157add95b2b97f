#!/usr/bin/python3
"""End to end: install the plugin into a temporary profile, run the provider
through qgis_process.bin, and check its numbers against an independent
implementation of the conventions.

    test_qgis_process.py SOURCE_DIR BUILD_DIR
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

from osgeo import ogr

import conventions_reference as ref

SOURCE_DIR, BUILD_DIR = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(SOURCE_DIR, "scripts"))
import geostation_demo_data  # noqa: E402
from headless_support import install_plugin, qgis_env  # noqa: E402




def install(home, *extra):
    install_plugin(SOURCE_DIR, BUILD_DIR, home, *extra)


def qgis_process(home, *args):
    return subprocess.run(["qgis_process.bin", *args], env=qgis_env(home), capture_output=True, text=True, timeout=300)


class QgisProcessTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="geostation-e2e-")
        cls.home = os.path.join(cls.tmp, "home")
        os.makedirs(cls.home)
        install(cls.home)
        cls.data = os.path.join(cls.tmp, "data")
        cls.block_path, _ = geostation_demo_data.make_demo_block(cls.data, stations=6, seed=3)
        with open(cls.block_path) as f:
            cls.block = json.load(f)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def run_projection(self, block, image_id, output, inputs=None):
        return qgis_process(self.home, "run", "geostation:project_to_image", "--",
                            "BLOCK=" + block, "IMAGE=" + image_id,
                            "INPUT=" + (inputs or os.path.join(self.data, "objects.gpkg")), "OUTPUT=" + output)

    def test_list_shows_the_provider(self):
        result = qgis_process(self.home, "list")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("geostation:project_to_image", result.stdout)

    def test_the_bridge_metadata_is_complete_and_has_no_placeholders(self):
        import configparser
        bridge = os.path.join(self.home, ".local", "share", "QGIS", "QGIS3", "profiles", "default", "python", "plugins", "geostation_processing")
        metadata = configparser.ConfigParser()
        metadata.read(os.path.join(bridge, "metadata.txt"))
        general = metadata["general"]
        # bound to the QGIS it was built against
        qgis_version = subprocess.run(["/usr/bin/python3", "-c", "from qgis.core import Qgis; print(Qgis.version())"],
                                      capture_output=True, text=True).stdout.strip()
        major_minor = ".".join(qgis_version.split(".")[:2])
        self.assertEqual(general["qgisMinimumVersion"], major_minor)
        self.assertEqual(general["qgisMaximumVersion"], major_minor + ".99")
        self.assertTrue(os.path.isfile(os.path.join(bridge, general["icon"])))
        self.assertIn("- ", general["changelog"])
        with open(os.path.join(bridge, "metadata.txt")) as f:
            self.assertNotIn("example.invalid", f.read())

    def test_pixels_match_the_conventions_for_every_camera_model(self):
        cameras = {c["id"]: c for c in self.block["cameras"]}
        objects = {}
        ds = ogr.Open(os.path.join(self.data, "objects.gpkg"))
        for f in ds.GetLayer(0):
            g = f.GetGeometryRef()
            objects[f.GetField("id")] = (g.GetX(), g.GetY(), g.GetZ())
        ds = None

        checked = in_frame = behind = 0
        for image in self.block["images"][6:9]:  # station 3: opencv, opencv, brown_photo
            output = os.path.join(self.tmp, image["id"] + ".gpkg")
            result = self.run_projection(self.block_path, image["id"], output)
            self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
            camera = cameras[image["camera"]]
            out = ogr.Open(output)
            layer = out.GetLayer(0)
            self.assertEqual(layer.GetSpatialRef().GetName(), "Undefined Cartesian SRS")
            for f in layer:
                expected = ref.project(camera, image, objects[f.GetField("id")])
                geometry = f.GetGeometryRef()
                if expected is None:
                    behind += 1
                    self.assertIsNone(geometry, f.GetField("id"))
                    self.assertFalse(f.GetField("in_frame"))
                    continue
                col, row = expected
                frame = 0 <= col < camera["width"] and 0 <= row < camera["height"]
                tolerance = 1e-6
                self.assertAlmostEqual(f.GetField("col"), col, delta=tolerance)
                self.assertAlmostEqual(f.GetField("row"), row, delta=tolerance)
                self.assertAlmostEqual(geometry.GetX(), col, delta=tolerance)
                self.assertAlmostEqual(geometry.GetY(), -row, delta=tolerance)
                self.assertEqual(bool(f.GetField("in_frame")), frame, f.GetField("id"))
                self.assertEqual(bool(f.GetField("visible")), frame)
                checked += 1
                in_frame += frame
            out = None
        # The test means something only if it saw points in and out of frame and behind.
        self.assertGreater(in_frame, 10)
        self.assertGreater(checked - in_frame, 3)
        self.assertGreater(behind, 3)

    def assert_fails_cleanly(self, block_text, image_id, expected):
        block = os.path.join(self.tmp, "bad.geostation.json")
        with open(block, "w") as f:
            f.write(block_text)
        output = os.path.join(self.tmp, "must-not-exist.gpkg")
        result = self.run_projection(block, image_id, output)
        self.assertNotEqual(result.returncode, 0)
        self.assertIn(expected, result.stdout + result.stderr)
        self.assertFalse(os.path.exists(output), "a failed run left an output file")

    def test_malformed_block(self):
        self.assert_fails_cleanly('{"format": "geostation-block",\n "version": 1,,', "S0001_front_left", "not valid JSON (line 2")

    def test_geographic_crs(self):
        block = dict(self.block, crs="EPSG:4326")
        self.assert_fails_cleanly(json.dumps(block), "S0001_front_left", "at $.crs: 'EPSG:4326' (WGS 84) is a geographic CRS")

    def test_unknown_camera(self):
        block = json.loads(json.dumps(self.block))
        block["images"][4]["camera"] = "roof"
        self.assert_fails_cleanly(json.dumps(block), "S0001_front_left", "at $.images[4].camera: camera \"roof\" is not defined")

    def test_missing_image_file(self):
        block = json.loads(json.dumps(self.block))
        block["images"][0]["path"] = os.path.join(self.data, "images", "lost.tif")
        self.assert_fails_cleanly(json.dumps(block), "S0001_front_left", "does not exist")

    def test_unknown_image_id(self):
        with open(self.block_path) as f:
            self.assert_fails_cleanly(f.read(), "S0099_front_left", "image \"S0099_front_left\" is not in the block")


class AdjustmentTest(unittest.TestCase):
    """intersect and resection through qgis_process, on observations computed
    with the independent reference implementation."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="geostation-e2e-adj-")
        cls.home = os.path.join(cls.tmp, "home")
        os.makedirs(cls.home)
        install(cls.home)
        cls.data = os.path.join(cls.tmp, "data")
        cls.block_path, _ = geostation_demo_data.make_demo_block(cls.data, stations=6, seed=4)
        with open(cls.block_path) as f:
            cls.block = json.load(f)
        cls.cameras = {c["id"]: c for c in cls.block["cameras"]}
        cls.images = {i["id"]: i for i in cls.block["images"]}
        cls.objects = {}
        ds = ogr.Open(os.path.join(cls.data, "objects.gpkg"))
        for f in ds.GetLayer(0):
            g = f.GetGeometryRef()
            cls.objects[f.GetField("id")] = (g.GetX(), g.GetY(), g.GetZ())
        ds = None

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def observe(self, image_ids):
        rows = []
        for image_id in image_ids:
            image = self.images[image_id]
            camera = self.cameras[image["camera"]]
            for point_id, xyz in self.objects.items():
                pixel = ref.project(camera, image, xyz)
                if pixel and 0 <= pixel[0] < camera["width"] and 0 <= pixel[1] < camera["height"]:
                    rows.append((point_id, image_id, pixel[0], pixel[1]))
        return rows

    def write_csv(self, name, header, rows):
        path = os.path.join(self.tmp, name)
        with open(path, "w") as f:
            f.write(",".join(header) + "\n")
            for r in rows:
                f.write(",".join(str(v) if not isinstance(v, float) else "%.10f" % v for v in r) + "\n")
        return path

    def test_intersect_recovers_the_objects(self):
        rows = self.observe(["S0003_front_left", "S0003_front_right", "S0003_side_right"])
        seen = {}
        for r in rows:
            seen.setdefault(r[0], []).append(r[1])
        observations = self.write_csv("obs.csv", ["point_id", "image_id", "col", "row"], rows)
        output = os.path.join(self.tmp, "points.gpkg")
        result = qgis_process(self.home, "run", "geostation:intersect", "--", "BLOCK=" + self.block_path,
                              "OBSERVATIONS=" + observations, "OUTPUT=" + output)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        ds = ogr.Open(output)
        layer = ds.GetLayer(0)
        self.assertIn("UTM zone 17N", layer.GetSpatialRef().GetName())
        count = 0
        for f in layer:
            if f.GetField("status") != "ok":
                # seen in one image only: kept with its status, without geometry
                self.assertEqual(f.GetField("status"), "too_few_rays")
                self.assertLess(len(seen[f.GetField("point_id")]), 2)
                continue
            g = f.GetGeometryRef()
            truth = self.objects[f.GetField("point_id")]
            for a, b in zip((g.GetX(), g.GetY(), g.GetZ()), truth):
                self.assertAlmostEqual(a, b, delta=1e-5)
            self.assertEqual(f.GetField("n_images"), len(seen[f.GetField("point_id")]))
            count += 1
        ds = None
        self.assertEqual(count, sum(1 for v in seen.values() if len(v) >= 2))
        self.assertGreater(count, 5)

    def test_resection_orients_an_unoriented_image(self):
        image_id = "S0002_front_left"
        block = json.loads(json.dumps(self.block))
        for image in block["images"]:
            if image["id"] == image_id:
                for key in ("X", "Y", "Z", "omega", "phi", "kappa", "sigma"):
                    image.pop(key)
        unoriented = os.path.join(self.data, "unoriented.geostation.json")
        with open(unoriented, "w") as f:
            json.dump(block, f)
        rows = self.observe([image_id])
        self.assertGreaterEqual(len(rows), 6)
        observations = self.write_csv("obs-resection.csv", ["point_id", "image_id", "col", "row"], rows)
        gcps = self.write_csv("gcps.csv", ["point_id", "X", "Y", "Z"], [(k,) + v for k, v in self.objects.items()])
        out_block = os.path.join(self.tmp, "oriented.geostation.json")
        report = os.path.join(self.tmp, "report.json")
        result = qgis_process(self.home, "run", "geostation:resection", "--", "BLOCK=" + unoriented, "IMAGE=" + image_id,
                              "GCPS=" + gcps, "OBSERVATIONS=" + observations, "OUTPUT_BLOCK=" + out_block, "REPORT=" + report)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        with open(out_block) as f:
            oriented = {i["id"]: i for i in json.load(f)["images"]}[image_id]
        truth = self.images[image_id]
        for key in ("X", "Y", "Z"):
            self.assertAlmostEqual(oriented[key], truth[key], delta=1e-5)
        for key in ("omega", "phi", "kappa"):
            self.assertAlmostEqual(oriented[key], truth[key], delta=1e-6)
        self.assertIn("sigma", oriented)
        with open(report) as f:
            data = json.load(f)
        self.assertTrue(data["converged"])
        self.assertEqual(len(data["parameters"]), 6)
        self.assertEqual(len(data["residuals"]), len(rows))

    def test_resection_with_too_few_points_fails_cleanly(self):
        rows = self.observe(["S0002_front_left"])[:3]
        observations = self.write_csv("obs-few.csv", ["point_id", "image_id", "col", "row"], rows)
        gcps = self.write_csv("gcps-few.csv", ["point_id", "X", "Y", "Z"], [(k,) + v for k, v in self.objects.items()])
        out_block = os.path.join(self.tmp, "never.geostation.json")
        result = qgis_process(self.home, "run", "geostation:resection", "--", "BLOCK=" + self.block_path, "IMAGE=S0002_front_left",
                              "GCPS=" + gcps, "OBSERVATIONS=" + observations, "OUTPUT_BLOCK=" + out_block,
                              "REPORT=" + os.path.join(self.tmp, "never.json"))
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("needs at least 4 control points", result.stdout + result.stderr)
        self.assertFalse(os.path.exists(out_block))


class SimulateSurveyTest(unittest.TestCase):
    """geostation:simulate_survey and geostation-simulate: the embedded highway
    preset (30 stations x 3 cameras, 640 x 480) and the interface contract."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="geostation-sim-e2e-")
        cls.home = os.path.join(cls.tmp, "home")
        os.makedirs(cls.home)
        install(cls.home)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_highway_preset_through_processing_and_the_command_line(self):
        out = os.path.join(self.tmp, "highway")
        started = time.monotonic()
        result = qgis_process(self.home, "run", "geostation:simulate_survey", "--", "PRESET=highway", "SEED=7", "OUTPUT_DIR=" + out)
        seconds = time.monotonic() - started
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        print("\nhighway preset (30 x 3 images, 640 x 480) through qgis_process: %.1f s" % seconds)
        self.assertIn("IMAGES:\t90", result.stdout)
        with open(os.path.join(out, "block.geostation.json")) as f:
            block = json.load(f)
        self.assertEqual(len(block["stations"]), 30)
        self.assertEqual(len(block["images"]), 90)
        self.assertEqual(block["cameras"][0]["width"], 640)
        for image in block["images"]:
            self.assertTrue(os.path.exists(os.path.join(out, image["path"])), image["path"])
            self.assertIn("sigma", image)
        truth = ogr.Open(os.path.join(out, "truth.gpkg"))
        layers = {truth.GetLayer(i).GetName(): truth.GetLayer(i) for i in range(truth.GetLayerCount())}
        for name, geometry, fields in [("objects", ogr.wkbPoint25D, ["id", "kind"]), ("roads", ogr.wkbLineString25D, ["id", "kind"]),
                                       ("control", ogr.wkbPoint25D, ["id"]), ("image_truth", ogr.wkbNone, ["point_id", "image_id", "col", "row"])]:
            self.assertIn(name, layers)
            layer = layers[name]
            self.assertEqual(layer.GetGeomType(), geometry, name)
            defn = layer.GetLayerDefn()
            self.assertEqual([defn.GetFieldDefn(i).GetName() for i in range(defn.GetFieldCount())][:len(fields)], fields)
            self.assertGreater(layer.GetFeatureCount(), 0, name)
        kinds = {f.GetField("kind") for f in layers["roads"]}
        self.assertEqual(kinds, {"centre", "edge", "marking", "kerb"})
        kinds = {f.GetField("kind") for f in layers["objects"]}
        self.assertTrue({"pole", "sign", "hydrant", "manhole"} <= kinds, kinds)
        self.assertGreater(layers["image_truth"].GetFeatureCount(), 10000)

        # the command line takes the same options and gives the same output
        cli_out = os.path.join(self.tmp, "highway-cli")
        cli = subprocess.run([os.path.join(BUILD_DIR, "core", "geostation-simulate"), "--quiet", "PRESET=highway", "SEED=7", "--output-dir", cli_out],
                             capture_output=True, text=True, timeout=300)
        self.assertEqual(cli.returncode, 0, cli.stderr)
        with open(os.path.join(cli_out, "block.geostation.json")) as f:
            self.assertEqual(json.load(f), block)

    def test_scanned_oblique_photo_oriented_from_its_targets_with_no_click(self):
        """Stokes' (1988) workflow headless: a scanned oblique photo gets its inner orientation from
        its fiducials, its control identified automatically, and its exterior orientation by resection."""
        out = os.path.join(self.tmp, "film")
        result = qgis_process(self.home, "run", "geostation:simulate_survey", "--", "PRESET=oblique_photo", "SCANNED_FILM=true", "SEED=8",
                              "NOISE=2", "OUTPUT_DIR=" + out)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        with open(os.path.join(out, "block.geostation.json")) as f:
            image_id = json.load(f)["images"][0]["id"]
        truth = ogr.Open(os.path.join(out, "truth.gpkg"))
        control = os.path.join(self.tmp, "film_control.csv")
        with open(control, "w") as f:
            f.write("point_id,X,Y,Z\n")
            for feature in truth.GetLayerByName("control"):
                g = feature.GetGeometryRef()
                f.write("%s,%.4f,%.4f,%.4f\n" % (feature.GetField("id"), g.GetX(), g.GetY(), g.GetZ()))
        true_pixels = {f.GetField("point_id"): (f.GetField("col"), f.GetField("row"))
                       for f in truth.GetLayerByName("image_truth") if f.GetField("image_id") == image_id}

        inner = os.path.join(self.tmp, "film_io.geostation.json")
        result = qgis_process(self.home, "run", "geostation:inner_orientation", "--", "BLOCK=" + os.path.join(out, "block.geostation.json"),
                              "IMAGE=" + image_id, "AUTO=true", "MARK_DIAMETER_PX=24", "OUTPUT_BLOCK=" + inner,
                              "REPORT=" + os.path.join(self.tmp, "film_io.json"))
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        identified = os.path.join(self.tmp, "film_identified.csv")
        result = qgis_process(self.home, "run", "geostation:identify_control", "--", "BLOCK=" + inner, "IMAGE=" + image_id,
                              "CONTROL=" + control, "USE_ORIENTATION=false", "OUTPUT=" + identified,
                              "REPORT=" + os.path.join(self.tmp, "film_identified.json"))
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        table = ogr.Open(identified)  # held: its layer dies with it
        rows = [r for r in table.GetLayer(0) if r.GetField("status") == "identified"]
        self.assertGreaterEqual(len(rows), 7)
        errors = [((r.GetFieldAsDouble("col") - true_pixels[r.GetField("point_id")][0]) ** 2 +
                   (r.GetFieldAsDouble("row") - true_pixels[r.GetField("point_id")][1]) ** 2) ** 0.5 for r in rows]
        self.assertLess(max(errors), 0.5, errors)

        oriented = os.path.join(self.tmp, "film_oriented.geostation.json")
        result = qgis_process(self.home, "run", "geostation:resection", "--", "BLOCK=" + inner, "IMAGE=" + image_id, "GCPS=" + control,
                              "OBSERVATIONS=" + identified, "OUTPUT_BLOCK=" + oriented, "REPORT=" + os.path.join(self.tmp, "film_resection.json"))
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        with open(oriented) as f:
            estimated = json.load(f)["images"][0]
        with open(os.path.join(out, "truth.geostation.json")) as f:
            exact = json.load(f)["images"][0]
        error_m = sum((estimated[k] - exact[k]) ** 2 for k in ("X", "Y", "Z")) ** 0.5
        print("\nscanned oblique photo, no click: %d targets identified (worst %.2f px), camera %.2f m from the truth" % (len(rows), max(errors), error_m))
        self.assertLess(error_m, 0.3)

    def test_bad_options_fail_with_one_sentence_and_no_output(self):
        out = os.path.join(self.tmp, "bad")
        result = qgis_process(self.home, "run", "geostation:simulate_survey", "--", "PRESET=highway", "IMAGE_WIDTH=10", "OUTPUT_DIR=" + out)
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("between 32 and 8000 pixels", result.stdout + result.stderr)
        self.assertFalse(os.path.exists(os.path.join(out, "block.geostation.json")))
        cli = subprocess.run([os.path.join(BUILD_DIR, "core", "geostation-simulate"), "--preset", "motorbike", "--output-dir", out],
                             capture_output=True, text=True)
        self.assertEqual(cli.returncode, 2)
        self.assertIn("unknown preset", cli.stderr)


class InstallTest(unittest.TestCase):
    def test_install_is_idempotent_and_uninstall_removes_everything(self):
        with tempfile.TemporaryDirectory(prefix="geostation-install-") as home:
            install(home)
            install(home)
            profile = os.path.join(home, ".local/share/QGIS/QGIS3/profiles/default")
            with open(os.path.join(profile, "QGIS/QGIS3.ini")) as f:
                ini = f.read()
            self.assertEqual(ini.count("geostation/plugins"), 1)
            self.assertIn("geostation:project_to_image", qgis_process(home, "list").stdout)

            install(home, "--uninstall")
            self.assertFalse(os.path.exists(os.path.join(profile, "geostation")))
            self.assertFalse(os.path.exists(os.path.join(profile, "python/plugins/geostation_processing")))
            with open(os.path.join(profile, "QGIS/QGIS3.ini")) as f:
                self.assertNotIn("geostation", f.read())
            self.assertNotIn("geostation:", qgis_process(home, "list").stdout)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
