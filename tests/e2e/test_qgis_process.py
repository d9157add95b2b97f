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
import unittest

from osgeo import ogr

import conventions_reference as ref

SOURCE_DIR, BUILD_DIR = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(SOURCE_DIR, "scripts"))
import geostation_demo_data  # noqa: E402


def qgis_env(home):
    env = dict(os.environ, HOME=home, QT_QPA_PLATFORM="offscreen", XDG_RUNTIME_DIR=home)
    env.pop("GEOSTATION_PROVIDER_LIBRARY", None)
    return env


def install(home, *extra):
    subprocess.run([os.path.join(SOURCE_DIR, "scripts", "install-plugin.sh"), "--build-dir", BUILD_DIR, *extra],
                   env=qgis_env(home), check=True, capture_output=True, text=True)


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
