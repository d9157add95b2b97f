#!/usr/bin/python3
"""End to end, the mapping-van case: a simulated highway run is written out the
way a van's processing software hands it over (an OpenCV calibration file per
rig with lever arms and boresights, and a trajectory CSV with roll, pitch and
heading from true north), geostation:import_block reads it back, and the block
must equal the simulator's truth.
    test_trajectory_import.py SOURCE_DIR BUILD_DIR

The trajectory is derived here from the truth block with an independent
inverse of the rig conventions: body x forward, y right, z down, heading from
true north (PROJ's meridian convergence through osr), lever arms in the body
frame, boresights as roll, pitch, heading of the camera in the body.
"""
import json
import math
import os
import shutil
import subprocess
import sys
import unittest

import numpy as np
from osgeo import osr

import conventions_reference as ref
from headless_support import qgis_env, temporary_profile  # noqa: E402

SOURCE_DIR, BUILD_DIR = sys.argv[1], sys.argv[2]
CRS = "EPSG:32617"
BODY_FROM_FORWARD_CAMERA = np.array([[0, 0, -1], [1, 0, 0], [0, -1, 0]], float)
ENU_FROM_NED = np.array([[0, 1, 0], [1, 0, 0], [0, 0, -1]], float)
CODES = {"front_left": "FL", "front_right": "FR", "side_right": "SR"}




def roll_pitch_heading(R):
    """Angles (deg) of R = Rz(heading) Ry(pitch) Rx(roll)."""
    pitch = -math.asin(max(-1.0, min(1.0, R[2, 0])))
    return (math.degrees(math.atan2(R[2, 1], R[2, 2])), math.degrees(pitch), math.degrees(math.atan2(R[1, 0], R[0, 0])))


def rot_z(deg):
    a = math.radians(deg)
    return np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])


def iso_seconds(text):
    """2026-05-04T10:00:00.417Z as seconds since 1970-01-01."""
    import datetime
    return datetime.datetime.strptime(text, "%Y-%m-%dT%H:%M:%S.%fZ").replace(tzinfo=datetime.timezone.utc).timestamp()


def iso_text(seconds):
    import datetime
    return datetime.datetime.fromtimestamp(seconds, datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%S.%f") + "Z"


class TrajectoryImportTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp, cls.home = temporary_profile(SOURCE_DIR, BUILD_DIR, "geostation-trajectory-")
        cls.sim = os.path.join(cls.tmp, "sim")
        subprocess.run([os.path.join(BUILD_DIR, "core", "geostation-simulate"), "--preset", "highway", "--output-dir", cls.sim, "--stations", "8",
                        "--cameras", "3", "--image-width", "320", "--image-height", "240", "--quiet"], check=True, capture_output=True)
        with open(os.path.join(cls.sim, "truth.geostation.json")) as f:
            cls.truth = json.load(f)
        cls.cameras = {c["id"]: c for c in cls.truth["cameras"]}
        images = {}
        for i in cls.truth["images"]:
            images.setdefault(i["station"], {})[i["camera"]] = i
        cls.stations = [s["id"] for s in cls.truth["stations"]]

        def pose(image):
            return np.array([image["X"], image["Y"], image["Z"]]), ref.rotation(image["omega"], image["phi"], image["kappa"])

        # the body: the front-left camera's forward frame; the rig from station 1
        cls.body = {}
        for s in cls.stations:
            centre, R = pose(images[s]["front_left"])
            cls.body[s] = (centre, R @ BODY_FROM_FORWARD_CAMERA.T)
        origin, world_from_body = cls.body[cls.stations[0]]
        cls.rig = {}
        for cam in CODES:
            centre, R = pose(images[cls.stations[0]][cam])
            cls.rig[cam] = (world_from_body.T @ (centre - origin), roll_pitch_heading(world_from_body.T @ R @ BODY_FROM_FORWARD_CAMERA.T))

        # meridian convergence with osr: the grid direction of true north
        utm, wgs84 = osr.SpatialReference(), osr.SpatialReference()
        utm.SetFromUserInput(CRS)
        wgs84.SetFromUserInput("EPSG:4326")
        for srs in (utm, wgs84):
            srs.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
        to_geo, to_grid = osr.CoordinateTransformation(utm, wgs84), osr.CoordinateTransformation(wgs84, utm)

        cls.data = os.path.join(cls.sim, "van")
        os.makedirs(cls.data)
        for variant in ("grid", "geographic"):
            with open(os.path.join(cls.sim, "trajectory-%s.csv" % variant), "w") as f:
                f.write("time,station,%s,roll,pitch,heading\n" % ("X,Y,Z" if variant == "grid" else "latitude,longitude,height"))
                for s, st in zip(cls.stations, cls.truth["stations"]):
                    centre, wfb = cls.body[s]
                    lon, lat, _ = to_geo.TransformPoint(*centre)
                    n0, n1 = np.array(to_grid.TransformPoint(lon, lat - 1e-4, 0)), np.array(to_grid.TransformPoint(lon, lat + 1e-4, 0))
                    gamma = -math.degrees(math.atan2(n1[0] - n0[0], n1[1] - n0[1]))
                    rph = roll_pitch_heading(ENU_FROM_NED.T @ rot_z(gamma).T @ wfb)
                    position = centre if variant == "grid" else (lat, lon, centre[2])
                    f.write("%s,%s,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n" % ((st["time"], s) + tuple(position) + rph))
        # a high-rate solution: the stations' own epochs and four samples between each two (linear between them),
        # and the exposure events at the stations' times plus one before the solution starts
        with open(os.path.join(cls.sim, "trajectory-grid.csv")) as f:
            rows = [line.rstrip("\n").split(",") for line in f][1:]
        with open(os.path.join(cls.sim, "ins-dense.csv"), "w") as f:
            f.write("time,X,Y,Z,roll,pitch,heading\n")
            for a, b in zip(rows, rows[1:] + [None]):
                f.write(",".join([a[0]] + a[2:]) + "\n")
                if b is None:
                    break
                ta, tb = iso_seconds(a[0]), iso_seconds(b[0])
                for k in range(1, 5):
                    w = k / 5.0
                    values = [(1 - w) * float(x) + w * float(y) for x, y in zip(a[2:5], b[2:5])] + [float(x) for x in a[5:8]]
                    f.write(iso_text(ta + w * (tb - ta)) + "," + ",".join("%.17g" % v for v in values) + "\n")
        with open(os.path.join(cls.sim, "events.csv"), "w") as f:
            f.write("time,station\n2026-05-04T09:59:00.000Z,EARLY\n")
            for r in rows:
                f.write("%s,%s\n" % (r[0], r[1]))
        with open(os.path.join(cls.sim, "rig.yaml"), "w") as f:
            f.write("%YAML:1.0\ncameras:\n")
            for cam, (lever, bore) in cls.rig.items():
                c = cls.cameras[cam]
                d = c["distortion"]
                f.write("  - id: %s\n    image_width: %d\n    image_height: %d\n" % (cam, c["width"], c["height"]))
                f.write("    camera_matrix: [ %.17g, 0., %.17g, 0., %.17g, %.17g, 0., 0., 1. ]\n"
                        % (c["f"], c["cx"] - 0.5, c["f"] * c.get("aspect", 1.0), c["cy"] - 0.5))
                f.write("    distortion_coefficients: [ %.17g, %.17g, %.17g, %.17g, %.17g ]\n" % (d["k1"], d["k2"], d["p1"], d["p2"], d["k3"]))
                f.write("    lever_arm: [ %.17g, %.17g, %.17g ]\n    boresight: [ %.17g, %.17g, %.17g ]\n" % (tuple(lever) + bore))
                f.write("    image_pattern: \"images/{station}_%s.tif\"\n" % CODES[cam])

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def qgis_process(self, algorithm, **params):
        args = ["qgis_process.bin", "run", "geostation:" + algorithm, "--"] + ["%s=%s" % kv for kv in params.items()]
        return subprocess.run(args, env=qgis_env(self.home), capture_output=True, text=True, timeout=300)

    def check_variant(self, variant, **extra):
        output = os.path.join(self.tmp, variant + ".geostation.json")
        trajectory = "ins-dense.csv" if variant == "events" else "trajectory-%s.csv" % variant
        result = self.qgis_process("import_block", INPUT=os.path.join(self.sim, "rig.yaml"), TRAJECTORY=os.path.join(self.sim, trajectory),
                                   CRS=CRS, OUTPUT_BLOCK=output, REPORT=os.path.join(self.tmp, variant + "-report.json"), **extra)
        self.assertEqual(result.returncode, 0, result.stdout + result.stderr)
        with open(output) as f:
            block = json.load(f)
        self.assertEqual(len(block["stations"]), len(self.stations))
        self.assertEqual(len(block["images"]), 3 * len(self.stations))
        truth = {(i["station"], i["camera"]): i for i in self.truth["images"]}
        worst_m = worst_r = 0.0
        for i in block["images"]:
            t = truth[(i["station"], i["camera"])]
            self.assertEqual(os.path.normpath(os.path.join(self.tmp, i["path"])), os.path.normpath(os.path.join(self.sim, t["path"])))
            worst_m = max(worst_m, math.dist((i["X"], i["Y"], i["Z"]), (t["X"], t["Y"], t["Z"])))
            worst_r = max(worst_r, float(np.abs(ref.rotation(i["omega"], i["phi"], i["kappa"]) - ref.rotation(t["omega"], t["phi"], t["kappa"])).max()))
        for c in block["cameras"]:
            t = self.cameras[c["id"]]
            for k in ("f", "cx", "cy", "width", "height"):
                self.assertAlmostEqual(c[k], t[k], delta=1e-9)
            self.assertEqual(c["distortion"], {k: t["distortion"][k] for k in c["distortion"]})
        self.assertEqual(block["stations"][0]["time"], self.truth["stations"][0]["time"])
        print("%s trajectory: %d images against the truth: centres within %.1e m, rotation elements within %.1e" % (variant, len(block["images"]), worst_m, worst_r))
        return worst_m, worst_r

    def test_grid_trajectory_reproduces_the_truth(self):
        worst_m, worst_r = self.check_variant("grid")
        self.assertLess(worst_m, 1e-8)
        self.assertLess(worst_r, 1e-12)

    def test_geographic_trajectory_reproduces_the_truth(self):
        worst_m, worst_r = self.check_variant("geographic")
        self.assertLess(worst_m, 1e-8)  # latitude/longitude through PROJ and back
        self.assertLess(worst_r, 1e-10)

    def test_events_in_a_high_rate_trajectory_reproduce_the_truth(self):
        # the events fall on the solution's own epochs: the poses there are the samples' (interpolation's maths: core tests)
        worst_m, worst_r = self.check_variant("events", EVENTS=os.path.join(self.sim, "events.csv"))
        self.assertLess(worst_m, 1e-8)
        self.assertLess(worst_r, 1e-12)
        with open(os.path.join(self.tmp, "events-report.json")) as f:
            report = json.load(f)
        self.assertEqual(len(report["dropped"]), 1)
        self.assertIn("event row 1 (time 2026-05-04T09:59:00.000Z): outside the trajectory's time span", report["dropped"][0])
        self.assertTrue(any("interpolated in the trajectory's %d samples" % (5 * len(self.stations) - 4) in c for c in report["converted"]), report["converted"])

    def test_missing_trajectory_or_images_write_nothing(self):
        output = os.path.join(self.tmp, "bad.geostation.json")
        result = self.qgis_process("import_block", INPUT=os.path.join(self.sim, "rig.yaml"), CRS=CRS, OUTPUT_BLOCK=output)
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("TRAJECTORY", result.stdout + result.stderr)
        result = self.qgis_process("import_block", INPUT=os.path.join(self.sim, "rig.yaml"), TRAJECTORY=os.path.join(self.sim, "trajectory-grid.csv"),
                                   IMAGES=self.tmp, CRS=CRS, OUTPUT_BLOCK=output)
        self.assertNotEqual(result.returncode, 0)
        self.assertIn("does not exist", result.stdout + result.stderr)
        self.assertFalse(os.path.exists(output))


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0], "-v"])
