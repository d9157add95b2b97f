#!/usr/bin/python3
"""End to end: every algorithm of the provider through qgis_process.bin with
only its required parameters and its main output, as a new user types it
from the help; then every output of every run read back, and no coordinate
or number in any of them may be NaN or infinite (features that cannot be
resolved keep their row and status with an empty geometry).

    test_headless_minimal.py SOURCE_DIR BUILD_DIR
"""

import csv
import json
import math
import os
import re
import shutil
import subprocess
import sys
import unittest

from osgeo import gdal, ogr, osr
from headless_support import qgis_env, temporary_profile  # noqa: E402

SOURCE_DIR, BUILD_DIR = sys.argv[1], sys.argv[2]

gdal.UseExceptions()
ogr.UseExceptions()

# the one output each algorithm is run for: its only mandatory destination, or the main one where all are optional
MAIN_OUTPUT = {"geostation:extract_roads": "OUTPUT"}




def non_finite_in_json(value):
    if isinstance(value, float):
        return not math.isfinite(value)
    if isinstance(value, dict):
        return any(non_finite_in_json(v) for v in value.values())
    if isinstance(value, list):
        return any(non_finite_in_json(v) for v in value)
    return False


def gpkg_blob_has_nan(blob):
    """True if a GeoPackage geometry blob holds a NaN or infinite coordinate (its WKB's doubles after the header)."""
    import struct
    flags = blob[3]
    envelope = {0: 0, 1: 32, 2: 48, 3: 48, 4: 64}.get((flags >> 1) & 7, 0)
    wkb = blob[8 + envelope:]
    order = "<" if wkb[0] == 1 else ">"
    header = 5  # byte order and type; the point's doubles follow, or counts and doubles for others
    doubles = [v for (v,) in struct.iter_unpack(order + "d", wkb[header:header + (len(wkb) - header) // 8 * 8])] if wkb[1:5] in (b"\x01\x00\x00\x00", b"\xe9\x03\x00\x00", b"\x00\x00\x00\x01", b"\x00\x00\x03\xe9") else []
    return any(not math.isfinite(v) for v in doubles)


NON_FINITE_TEXT = re.compile(r"(?<![A-Za-z_])(nan|-?inf|-?infinity)(?![A-Za-z_])", re.IGNORECASE)


class HeadlessMinimalTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp, cls.home = temporary_profile(SOURCE_DIR, BUILD_DIR, "geostation-minimal-")
        listing = json.loads(cls.qgis("--json", "list").stdout)
        cls.algorithms = sorted(listing["providers"]["geostation"]["algorithms"])
        cls.help = {a: json.loads(cls.qgis("--json", "help", a).stdout) for a in cls.algorithms}
        cls.outputs = {}

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def qgis(cls, *args):
        return subprocess.run(["qgis_process.bin", *args], env=qgis_env(cls.home), capture_output=True, text=True, timeout=600)

    def path(self, *parts):
        return os.path.join(self.tmp, *parts)

    def required(self, algorithm):
        """The parameters a user must give (no default) and the main output."""
        params = self.help[algorithm]["parameters"]
        inputs = sorted(n for n, p in params.items() if not p["is_destination"] and not p["optional"] and p["default_value"] is None)
        mandatory = [n for n, p in params.items() if p["is_destination"] and not p["optional"]]
        return inputs, mandatory

    def run_minimal(self, algorithm, inputs, output):
        """Runs with exactly the required inputs (checked against the help) and the main output."""
        required, mandatory = self.required(algorithm)
        self.assertEqual(sorted(inputs), required, algorithm + ": the required inputs")
        main = MAIN_OUTPUT.get(algorithm, mandatory[0] if mandatory else None)
        self.assertIsNotNone(main, algorithm)
        args = ["run", algorithm, "--"] + ["%s=%s" % (k, v) for k, v in inputs.items()] + ["%s=%s" % (main, output)]
        result = self.qgis(*args)
        self.assertNotIn("mandatory parameters were not specified", result.stdout + result.stderr)
        self.assertEqual(result.returncode, 0, algorithm + ":\n" + result.stdout + result.stderr)
        self.assertTrue(os.path.exists(output), algorithm + ": " + output)
        self.outputs[algorithm] = output
        return result

    # --- the runs, in an order that lets one feed the next ------------------------------------------------------

    def test_0_only_the_main_output_is_mandatory(self):
        self.assertEqual(len(self.algorithms), 19, self.algorithms)
        for algorithm in self.algorithms:
            params = self.help[algorithm]["parameters"]
            mandatory = [n for n, p in params.items() if p["is_destination"] and not p["optional"]]
            self.assertLessEqual(len(mandatory), 1, "%s: %s" % (algorithm, mandatory))
            for name, p in params.items():
                if p["is_destination"] and p["optional"] and name != MAIN_OUTPUT.get(algorithm):
                    self.assertFalse(p["raw_definition"].get("create_by_default", True),
                                     "%s: %s is written only when asked for" % (algorithm, name))

    def test_1_every_algorithm_with_its_required_parameters(self):
        hw = self.path("highway")
        self.run_minimal("geostation:simulate_survey", {}, hw)
        block = os.path.join(hw, "block.geostation.json")
        truth = os.path.join(hw, "truth.gpkg")
        image_truth = truth + "|layername=image_truth"
        self.run_minimal("geostation:project_to_image", {"BLOCK": block, "IMAGE": "S0003_FL", "INPUT": truth + "|layername=objects"},
                         self.path("projected.gpkg"))
        self.run_minimal("geostation:intersect", {"BLOCK": block, "OBSERVATIONS": image_truth}, self.path("intersected.gpkg"))
        self.run_minimal("geostation:bundle_adjust", {"BLOCK": block, "OBSERVATIONS": image_truth}, self.path("adjusted.geostation.json"))
        self.run_minimal("geostation:enhance_image", {"INPUT": os.path.join(hw, "images", "S0003_FL.tif")}, self.path("enhanced.tif"))
        # the reference points of one image, found in the station's other images
        reference = self.path("reference.csv")
        ds = gdal.OpenEx(truth, gdal.OF_VECTOR)
        with open(reference, "w") as f:
            f.write("point_id,image_id,col,row\n")
            for feature in ds.GetLayerByName("image_truth"):
                if feature.GetField("image_id") == "S0003_FL":
                    f.write("%s,S0003_FL,%.3f,%.3f\n" % (feature.GetField("point_id"), feature.GetField("col"), feature.GetField("row")))
        ds = None
        self.run_minimal("geostation:match_points", {"BLOCK": block, "OBSERVATIONS": reference}, self.path("matched.csv"))
        seeds = self.path("seeds.csv")
        subprocess.run(["/usr/bin/python3", os.path.join(SOURCE_DIR, "scripts", "demo_seeds.py"), hw, "S0003_FL", "S0003_FR", seeds], check=True,
                       capture_output=True)
        self.run_minimal("geostation:trace_road_lines", {"BLOCK": block, "SEEDS": seeds}, self.path("traced.gpkg"))
        colmap = os.path.join(hw, "colmap")  # beside the images, where COLMAP and the importer look for them
        self.run_minimal("geostation:export_block", {"BLOCK": block}, colmap)
        with open(block) as f:
            crs = json.load(f)["crs"]
        self.run_minimal("geostation:import_block", {"INPUT": colmap, "CRS": crs}, self.path("imported.geostation.json"))

        film = self.path("film")
        result = self.qgis("run", "geostation:simulate_survey", "--", "PRESET=oblique_photo", "SCANNED_FILM=true", "SEED=8", "OUTPUT_DIR=" + film)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        film_block = os.path.join(film, "block.geostation.json")
        film_truth = os.path.join(film, "truth.gpkg")
        self.run_minimal("geostation:inner_orientation", {"BLOCK": film_block, "IMAGE": "S0001"}, self.path("film_io.geostation.json"))
        film_io = self.path("film_io.geostation.json")
        self.run_minimal("geostation:identify_control", {"BLOCK": film_io, "IMAGE": "S0001", "CONTROL": film_truth + "|layername=control"},
                         self.path("film_identified.csv"))
        film_obs = self.path("film_observations.csv")
        ds = gdal.OpenEx(film_truth, gdal.OF_VECTOR)
        with open(film_obs, "w") as f:
            f.write("point_id,image_id,col,row\n")
            for feature in ds.GetLayerByName("image_truth"):
                if feature.GetField("point_id").startswith("GCP"):
                    f.write("%s,S0001,%.3f,%.3f\n" % (feature.GetField("point_id"), feature.GetField("col"), feature.GetField("row")))
        ds = None
        self.run_minimal("geostation:resection", {"BLOCK": film_io, "IMAGE": "S0001", "GCPS": film_truth + "|layername=control", "OBSERVATIONS": film_obs},
                         self.path("film_oriented.geostation.json"))
        # a batch with features that cannot be resolved: a point outside the frame, an empty point, a line leaving the frame
        features = self.path("film_features.gpkg")
        driver = ogr.GetDriverByName("GPKG")
        ds = driver.CreateDataSource(features)
        layer = ds.CreateLayer("features", None, ogr.wkbUnknown)
        layer.CreateField(ogr.FieldDefn("name", ogr.OFTString))
        for name, wkt in [("ground", "POINT (512 -600)"), ("outside", "POINT (-80 -40)"), ("empty", "POINT EMPTY"),
                          ("leaving", "LINESTRING (500 -600, -200 -600)"), ("sky", "POINT (512 -1)")]:
            f = ogr.Feature(layer.GetLayerDefn())
            f.SetField("name", name)
            f.SetGeometry(ogr.CreateGeometryFromWkt(wkt))
            layer.CreateFeature(f)
        ds = None
        self.run_minimal("geostation:monoplot", {"BLOCK": film_io, "IMAGE": "S0001", "DEM": os.path.join(film, "terrain.tif"), "INPUT": features},
                         self.path("monoplotted.gpkg"))
        ds = ogr.Open(self.path("monoplotted.gpkg"))
        status = {}
        for f in ds.GetLayer(0):
            g = f.GetGeometryRef()
            status[f.GetField("name")] = (f.GetField("status"), g.Clone() if g is not None else None)
        self.assertEqual(status["ground"][0], "ok")
        for name in ("outside", "empty"):
            self.assertNotEqual(status[name][0], "ok", name)
            self.assertTrue(status[name][1] is None or status[name][1].IsEmpty(), name)
        ds = None
        # a measurement GeoPackage for the CAD export: the monoplotted features
        self.run_minimal("geostation:export_measurements", {"INPUT": self.path("monoplotted.gpkg")}, self.path("cad"))

        aerial = self.path("aerial")
        result = self.qgis("run", "geostation:simulate_survey", "--", "PRESET=aerial_stereo", "STATIONS=2", "IMAGE_WIDTH=768", "IMAGE_HEIGHT=768",
                           "OUTPUT_DIR=" + aerial)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        self.run_minimal("geostation:extract_roads", {"BLOCK": os.path.join(aerial, "block.geostation.json"), "LEFT": "S0001", "RIGHT": "S0002"},
                         self.path("roads.gpkg"))
        self.run_minimal("geostation:merge_road_networks", {"INPUTS": self.path("roads.gpkg")}, self.path("merged.gpkg"))
        # two pieces of one line, as a plain CSV table with WKT
        with open(self.path("pieces.csv"), "w") as f:
            f.write('WKT,line_id,piece\n"LINESTRING Z (0 0 1,10 0 1,20 0 1)",a,1\n"LINESTRING Z (15 0 1,30 0 1)",a,2\n')
        self.run_minimal("geostation:join_traced_pieces", {"INPUT": self.path("pieces.csv")}, self.path("joined.gpkg"))
        # the simulation's own roads as the map (no CRS given: the block's)
        self.run_minimal("geostation:revise_roads", {"BLOCK": os.path.join(aerial, "block.geostation.json"), "LEFT": "S0001", "RIGHT": "S0002",
                                                     "MAP": os.path.join(aerial, "truth.gpkg") + "|layername=roads"},
                         self.path("revised.gpkg"))
        # the same pair's revision with its vertex table, as one pair of a strip: merge_revisions needs both
        pair = self.path("S0001-S0002.gpkg")
        result = self.qgis("run", "geostation:revise_roads", "--", "BLOCK=" + os.path.join(aerial, "block.geostation.json"), "LEFT=S0001", "RIGHT=S0002",
                           "MAP=" + os.path.join(aerial, "truth.gpkg") + "|layername=roads", "OUTPUT=" + pair, "VERTICES=" + self.path("S0001-S0002-vertices.gpkg"))
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        self.run_minimal("geostation:merge_revisions", {"INPUTS": pair, "VERTICES": self.path("S0001-S0002-vertices.gpkg")}, self.path("merged-revision.gpkg"))
        self.assertEqual(sorted(self.outputs), self.algorithms)
        self.check_every_output_is_finite()

    def test_2_bad_input_gets_one_sentence_and_no_output(self):
        """Inputs a new user hands over by mistake: each fails with one sentence naming the cause, and writes nothing."""
        hw = self.path("highway")
        block = os.path.join(hw, "block.geostation.json")
        self.assertTrue(os.path.exists(block), "test_1 simulates the data")

        def refused(algorithm, output, *params):
            result = self.qgis("run", algorithm, "--", *params, "%s=%s" % (output[0], output[1]))
            text = result.stdout + result.stderr
            self.assertNotEqual(result.returncode, 0, algorithm + ": " + text)
            self.assertNotIn("Segmentation", text)
            self.assertFalse(os.path.exists(output[1]), algorithm + ": " + output[1])
            return text

        # a DEM of NaN only, and one of nodata only, over the run: the DEM is named, not the stereo partner
        with open(block) as f:
            crs = json.load(f)["crs"]
        xs = [i["X"] for i in json.load(open(block))["images"]]
        ys = [i["Y"] for i in json.load(open(block))["images"]]
        for name, value, nodata in [("nan", float("nan"), None), ("nodata", -9999.0, -9999.0)]:
            dem = self.path("dem_%s.tif" % name)
            ds = gdal.GetDriverByName("GTiff").Create(dem, 100, 100, 1, gdal.GDT_Float32)
            ds.SetGeoTransform([min(xs) - 100, (max(xs) - min(xs) + 200) / 100.0, 0, max(ys) + 100, 0, -(max(ys) - min(ys) + 200) / 100.0])
            srs = osr.SpatialReference()
            srs.SetFromUserInput(crs)
            ds.SetProjection(srs.ExportToWkt())
            band = ds.GetRasterBand(1)
            if nodata is not None:
                band.SetNoDataValue(nodata)
            band.Fill(value)
            ds = None
            text = refused("geostation:trace_road_lines", ("OUTPUT", self.path("never_%s.gpkg" % name)), "BLOCK=" + block, "SEEDS=" + self.path("seeds.csv"), "DEM=" + dem)
            self.assertIn("the DEM", text)
            self.assertNotIn("no stereo partner", text)

        # a control point beyond any plausible position
        gcps = self.path("gcps_far.csv")
        ds = gdal.OpenEx(os.path.join(hw, "truth.gpkg"), gdal.OF_VECTOR)
        with open(gcps, "w") as f:
            f.write("point_id,X,Y,Z\n")
            for k, feature in enumerate(ds.GetLayerByName("control")):
                g = feature.GetGeometryRef()
                f.write("%s,%s,%.3f,%.3f\n" % (feature.GetField("id"), "1e308" if k == 0 else "%.3f" % g.GetX(), g.GetY(), g.GetZ()))
        ds = None
        image_truth = os.path.join(hw, "truth.gpkg") + "|layername=image_truth"
        for algorithm, params in [("geostation:bundle_adjust", ["BLOCK=" + block, "OBSERVATIONS=" + image_truth, "GCPS=" + gcps]),
                                  ("geostation:resection", ["BLOCK=" + block, "IMAGE=S0003_FL", "OBSERVATIONS=" + image_truth, "GCPS=" + gcps])]:
            text = refused(algorithm, ("OUTPUT_BLOCK", self.path("never.geostation.json")), *params)
            self.assertIn("beyond any plausible position", text)
            self.assertNotIn("Residual and Jacobian", text)
            self.assertNotIn("on one line", text)

        # a control layer with an empty point
        control = self.path("control_empty.gpkg")
        out = ogr.GetDriverByName("GPKG").CreateDataSource(control)
        film_srs = osr.SpatialReference()
        with open(self.path("film_io.geostation.json")) as f:
            film_srs.SetFromUserInput(json.load(f)["crs"])
        layer = out.CreateLayer("control", film_srs, ogr.wkbPoint25D)
        layer.CreateField(ogr.FieldDefn("point_id", ogr.OFTString))
        for name, wkt in [("A", "POINT Z (500000 4400000 200)"), ("B", "POINT EMPTY")]:
            f = ogr.Feature(layer.GetLayerDefn())
            f.SetField("point_id", name)
            f.SetGeometry(ogr.CreateGeometryFromWkt(wkt))
            layer.CreateFeature(f)
        out = None
        text = refused("geostation:identify_control", ("OUTPUT", self.path("never.csv")), "BLOCK=" + self.path("film_io.geostation.json"), "IMAGE=S0001",
                       "CONTROL=" + control)
        self.assertIn("(B)", text)
        self.assertIn("empty geometry", text)

        # a choice given by its index, as QGIS takes any enum's
        result = self.qgis("run", "geostation:extract_roads", "--", "BLOCK=" + os.path.join(self.path("aerial"), "block.geostation.json"), "LEFT=S0001",
                           "RIGHT=S0002", "POLARITY=0", "OUTPUT_LEFT=" + self.path("roads_left.gpkg"))
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)

    def check_every_output_is_finite(self):
        files = []
        for output in self.outputs.values():
            if os.path.isdir(output):
                files += [os.path.join(d, n) for d, _, names in os.walk(output) for n in names]
            else:
                files.append(output)
        checked = 0
        for path in files:
            ext = os.path.splitext(path)[1].lower()
            if ext == ".gpkg":
                # the stored blobs themselves: GDAL reads an empty point back as POINT EMPTY, but it is stored as NaN, NaN
                import sqlite3
                with sqlite3.connect(path) as db:
                    for table, column in db.execute("SELECT table_name, column_name FROM gpkg_geometry_columns").fetchall():
                        for (blob,) in db.execute('SELECT "%s" FROM "%s" WHERE "%s" IS NOT NULL' % (column, table, column)):
                            self.assertFalse(gpkg_blob_has_nan(blob), "%s: a geometry of %s is stored with NaN coordinates" % (path, table))
            if ext in (".gpkg", ".shp", ".dxf"):
                ds = ogr.Open(path)
                for i in range(ds.GetLayerCount()):
                    for feature in ds.GetLayer(i):
                        g = feature.GetGeometryRef()
                        if g is not None and not g.IsEmpty():
                            self.assertIsNone(NON_FINITE_TEXT.search(g.ExportToWkt()), "%s: %s" % (path, g.ExportToWkt()))
                        for k in range(feature.GetFieldCount()):
                            v = feature.GetField(k)
                            if isinstance(v, float):
                                self.assertTrue(math.isfinite(v), "%s: field %d of feature %d is %r" % (path, k, feature.GetFID(), v))
                        checked += 1
                ds = None
            elif ext in (".csv", ".txt"):
                with open(path, newline="") as f:
                    for row in csv.reader(f, delimiter="," if ext == ".csv" else " "):
                        for cell in row:
                            self.assertIsNone(NON_FINITE_TEXT.fullmatch(cell.strip()), "%s: %r" % (path, row))
                        checked += 1
            elif ext == ".json":
                with open(path) as f:
                    self.assertFalse(non_finite_in_json(json.load(f, parse_constant=lambda c: float(c))), path)
                checked += 1
        print("\n%d outputs of %d algorithms read back, %d rows: no NaN or infinite value" % (len(files), len(self.outputs), checked))
        self.assertGreater(checked, 100)


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0], "-v"])
