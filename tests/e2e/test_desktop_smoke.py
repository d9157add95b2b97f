#!/usr/bin/python3
"""QGIS desktop smoke test: installs GeoStation into a temporary profile,
starts qgis.bin under xvfb-run with desktop_smoke_script.py, and checks what
the script found: menu, toolbar, provider, block errors in the message bar.
The screenshot is kept as a test artifact.

    test_desktop_smoke.py SOURCE_DIR BUILD_DIR ARTIFACT_DIR
"""

import json
import os
import shutil
import sys
import tempfile
import unittest

SOURCE_DIR, BUILD_DIR, ARTIFACT_DIR = sys.argv[1:4]
sys.path.insert(0, os.path.join(SOURCE_DIR, "scripts"))
import geostation_demo_data  # noqa: E402
import desktop_harness  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


class DesktopSmokeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="geostation-desktop-")
        env, profiles = desktop_harness.install_plugin(SOURCE_DIR, BUILD_DIR, cls.tmp)
        data = os.path.join(cls.tmp, "data")
        block, _ = geostation_demo_data.make_demo_block(data, stations=3, seed=5)
        with open(block) as f:
            bad = json.load(f)
        bad["crs"] = "EPSG:4326"
        bad_path = os.path.join(data, "geographic.geostation.json")
        with open(bad_path, "w") as f:
            json.dump(bad, f)

        os.makedirs(ARTIFACT_DIR, exist_ok=True)
        cls.screenshot = os.path.join(ARTIFACT_DIR, "desktop-smoke.png")
        result_path = os.path.join(cls.tmp, "result.json")
        env.update(GEOSTATION_SMOKE_RESULT=result_path, GEOSTATION_SMOKE_SCREENSHOT=cls.screenshot,
                   GEOSTATION_SMOKE_BLOCK=block, GEOSTATION_SMOKE_BAD_BLOCK=bad_path,
                   GEOSTATION_SMOKE_OBJECTS=os.path.join(data, "objects.gpkg"))
        cls.exit_code, cls.log = desktop_harness.run_qgis(os.path.join(HERE, "desktop_smoke_script.py"), env, profiles)
        cls.result = {}
        if os.path.exists(result_path):
            with open(result_path) as f:
                cls.result = json.load(f)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_qgis_ran_the_script_and_quit_cleanly(self):
        self.assertTrue(self.result, "the script inside QGIS wrote nothing:\n" + self.log)
        self.assertNotIn("exception", self.result, self.result.get("exception"))
        self.assertEqual(self.exit_code, 0, self.log)

    def test_menu_toolbar_and_provider_are_present(self):
        self.assertTrue(self.result.get("menu"))
        self.assertEqual(self.result.get("menu_title"), "&GeoStation")
        self.assertIn("mActionGeoStationOpenBlock", self.result.get("menu_actions", []))
        self.assertIn("mActionGeoStationBlockInfo", self.result.get("menu_actions", []))
        self.assertIn("mActionGeoStationProjectToImage", self.result.get("menu_actions", []))
        self.assertTrue(self.result.get("toolbar"))
        self.assertEqual(self.result.get("adjustment_actions"), ["mActionGeoStationIntersect", "mActionGeoStationResection",
                                                                  "mActionGeoStationBundleAdjust", "mActionGeoStationInnerOrientation"])
        self.assertEqual(self.result.get("algorithms"), ["geostation:bundle_adjust", "geostation:enhance_image", "geostation:export_block",
                                                         "geostation:export_measurements", "geostation:extract_roads", "geostation:identify_control", "geostation:import_block",
                                                         "geostation:inner_orientation", "geostation:intersect",
                                                         "geostation:match_points", "geostation:monoplot", "geostation:project_to_image", "geostation:resection",
                                                         "geostation:simulate_survey", "geostation:trace_road_lines"])
        self.assertIn("mActionGeoStationMonoplot", self.result.get("menu_actions", []))
        self.assertIn("mActionGeoStationImportBlock", self.result.get("menu_actions", []))
        self.assertIn("mActionGeoStationExtractRoads", self.result.get("menu_actions", []))
        self.assertIn("mActionGeoStationReviewExtracted", self.result.get("menu_actions", []))
        self.assertTrue(self.result.get("provider"))
        self.assertTrue(self.result.get("algorithm"))
        self.assertGreater(self.result.get("processing_in_frame", 0), 0)

    def test_a_bad_block_gives_one_clear_message(self):
        self.assertTrue(self.result.get("plugin_object"))
        self.assertFalse(self.result.get("bad_block_opened"))
        messages = self.result.get("bad_block_messages", [])
        self.assertEqual(len(messages), 1, messages)
        self.assertEqual(messages[0]["level"], 2)  # Qgis.Critical
        self.assertIn("at $.crs", messages[0]["text"])
        self.assertIn("geographic", messages[0]["text"])

    def test_a_good_block_opens(self):
        self.assertTrue(self.result.get("good_block_opened"))
        messages = self.result.get("good_block_messages", [])
        self.assertEqual(len(messages), 1, messages)
        self.assertIn("3 cameras, 3 stations, 9 images (9 oriented)", messages[0]["text"])

    def test_block_information_shows_the_cameras(self):
        info = self.result.get("block_info", {})
        self.assertTrue(info.get("action_enabled"), info)
        self.assertEqual(info.get("dialog"), "GeoStationBlockInfoDialog")
        self.assertEqual(info.get("camera_rows"), 3)
        self.assertTrue(info.get("screenshot"))

    def test_menu_opens_the_algorithm_dialog(self):
        self.assertEqual(self.result.get("resection_dialog", {}).get("title"), "Space resection of an image")

    def test_screenshot_saved(self):
        self.assertTrue(self.result.get("screenshot"))
        self.assertGreater(os.path.getsize(self.screenshot), 10000)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
