#!/usr/bin/python3
"""QGIS desktop smoke test: installs GeoStation into a temporary profile,
starts qgis.bin under xvfb-run with desktop_smoke_script.py, and checks what
the script found: menu, toolbar, provider, block errors in the message bar,
and GeoStation > Import Block... run through its dialog on the demo run
written as a COLMAP 3.12 model with a rig and frames (the Multiview opens
on it station by station; the orientations are the run's). The screenshot
is kept as a test artifact.

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
import colmap_rig_model  # noqa: E402
import desktop_harness  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


class DesktopSmokeTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="geostation-desktop-")
        env, profiles = desktop_harness.install_plugin(SOURCE_DIR, BUILD_DIR, cls.tmp)
        data = os.path.join(cls.tmp, "data")
        block, _ = geostation_demo_data.make_demo_block(data, stations=3, seed=5)
        cls.demo_block = block
        # the run's two front cameras as a COLMAP 3.12 model: a rig, one frame per station
        cls.colmap_model = os.path.join(data, "sparse")
        cls.frames = colmap_rig_model.write_rig_model(block, cls.colmap_model)
        cls.imported_block = os.path.join(data, "imported.geostation.json")
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
                   GEOSTATION_SMOKE_OBJECTS=os.path.join(data, "objects.gpkg"),
                   GEOSTATION_SMOKE_COLMAP=cls.colmap_model, GEOSTATION_SMOKE_IMPORTED=cls.imported_block)
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

    def test_every_toolbar_button_has_an_icon_of_its_own(self):
        icons = self.result.get("toolbar_icons", {})
        self.assertGreaterEqual(len(icons), 6, icons.keys())
        for name, image in icons.items():
            self.assertIsNotNone(image, name + " has no icon")
        self.assertEqual(len(set(icons.values())), len(icons), "two toolbar buttons share an icon")
        self.assertTrue(self.result.get("provider_icon"), "the Processing provider has no icon")

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
                                                         "geostation:inner_orientation", "geostation:intersect", "geostation:join_traced_pieces",
                                                         "geostation:match_points", "geostation:merge_revisions", "geostation:merge_road_networks", "geostation:monoplot", "geostation:project_to_image", "geostation:resection",
                                                         "geostation:revise_roads",
                                                         "geostation:simulate_survey", "geostation:trace_road_lines"])
        self.assertIn("mActionGeoStationMonoplot", self.result.get("menu_actions", []))
        self.assertIn("mActionGeoStationReviewRevision", self.result.get("menu_actions", []))
        self.assertIn("mActionGeoStationReviseRoads", self.result.get("menu_actions", []))
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

    def test_the_dialog_has_a_help_button_and_the_menu_the_user_guide(self):
        # the Help button shows only for an algorithm whose help page is installed
        self.assertTrue(self.result.get("resection_dialog", {}).get("help_button"), self.result.get("resection_dialog"))
        self.assertTrue(self.result.get("user_guide_action"))

    def test_the_dialog_starts_with_the_open_block_and_image(self):
        dialog = self.result.get("resection_dialog", {})
        self.assertEqual(os.path.realpath(dialog.get("block") or ""), os.path.realpath(self.demo_block), dialog)
        self.assertTrue(dialog.get("image"), dialog)

    def test_import_block_opens_a_colmap_rig_run_station_by_station(self):
        seen = self.result.get("import_dialog", {})
        self.assertEqual(seen.get("title"), "Import block (COLMAP, Metashape, calibration + trajectory)", seen)
        self.assertTrue(seen.get("successful"), seen)
        self.assertEqual(seen.get("results", {}).get("IMAGES_IMPORTED"), "6", seen)
        # the Multiview shows the first of the three frames, with both cameras' images
        self.assertEqual(seen.get("dock_title"), "GeoStation Multiview — station S0001_front_left (1 of %d)" % self.frames, seen)
        self.assertEqual(seen.get("views"), 2, seen)
        # the imported orientations are the run's: centres to a micrometre, angles to 1e-6 degrees
        with open(self.demo_block) as f:
            truth = {image["id"]: image for image in json.load(f)["images"]}
        with open(self.imported_block) as f:
            imported = json.load(f)
        self.assertEqual(len(imported["stations"]), self.frames)
        self.assertEqual(len(imported["images"]), 6)
        for image in imported["images"]:
            expected = truth[image["id"]]
            self.assertEqual(image["station"], expected["station"] + "_front_left")
            for key in ("X", "Y", "Z"):
                self.assertAlmostEqual(image[key], expected[key], delta=1e-6, msg=image["id"])
            for key in ("omega", "phi", "kappa"):
                self.assertAlmostEqual((image[key] - expected[key] + 180.0) % 360.0 - 180.0, 0.0, delta=1e-6, msg=image["id"])

    def test_screenshot_saved(self):
        self.assertTrue(self.result.get("screenshot"))
        self.assertGreater(os.path.getsize(self.screenshot), 10000)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
