"""geostation-batch on a real Dask cluster on the loopback interface: a
dask-scheduler and two dask-worker processes, started and stopped here.

- extract over a simulated aerial strip of 5 images (4 stereo pairs): the
  merged network has no road twice, and scores against the truth no worse
  than each pair did on its own where that pair sees the ground;
- a worker killed with SIGKILL mid-run: the output equals the undisturbed
  run's;
- a unit that always fails (a corrupt image): named in the report, every
  other unit merged, exit status 3;
- a client killed and started again: only the missing units run;
- monoplot and project in chunks: every feature once, with its id, in order,
  equal to one qgis_process run of the whole layer;
- trace of a 200-station run from seeds every 50 stations: one continuous
  line per line_id, the same as one trace through the run where the pieces
  have settled, and as close to the truth everywhere;
- revise of a changed map over the strip: each map road once, its
  stretches end to end, confirmed at least as far as the pair that
  confirms it most.

    test_batch.py SOURCE_DIR BUILD_DIR
"""

import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import numpy as np
from osgeo import ogr

import batch_support as bs
from headless_support import install_plugin, qgis_env

SOURCE_DIR, BUILD_DIR = None, None
BUFFER_M = 3.0  # the buffer of the scores: half the narrowest road


class BatchOnALoopbackCluster(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="geostation-batch-test-")
        cls.home = os.path.join(cls.tmp, "home")
        os.makedirs(cls.home)
        install_plugin(SOURCE_DIR, BUILD_DIR, cls.home)
        cls.strip = os.path.join(cls.tmp, "strip")
        cls.qgis("run", "geostation:simulate_survey", "--", "PRESET=aerial_stereo", "STATIONS=5", "GSD=0.5", "SEED=3", "NOISE=4",
                 "OUTPUT_DIR=" + cls.strip)
        cls.block = os.path.join(cls.strip, "block.geostation.json")
        cls.cluster = bs.LoopbackCluster(os.path.join(cls.tmp, "cluster"), 2)

    @classmethod
    def tearDownClass(cls):
        cls.cluster.stop()
        shutil.rmtree(cls.tmp, ignore_errors=True)

    @classmethod
    def qgis(cls, *args):
        done = subprocess.run(["qgis_process.bin", *args], env=qgis_env(cls.home), capture_output=True, text=True, timeout=900)
        if done.returncode != 0:
            raise AssertionError(" ".join(args[:2]) + ":\n" + done.stdout + done.stderr)
        return done

    def extract(self, name, *extra, block=None, wait=True, log=None):
        out = os.path.join(self.tmp, name, "roads.gpkg")
        os.makedirs(os.path.dirname(out), exist_ok=True)
        return out, bs.batch(self.home, "extract", "--block", block or self.block, "--output", out,
                             "--scheduler", self.cluster.address, *extra, wait=wait, log=log)

    def footprint(self, image):
        """The ground an image sees: its frame monoplotted onto the terrain."""
        frame = os.path.join(self.tmp, "frame.gpkg")
        if not os.path.exists(frame):
            ds = ogr.GetDriverByName("GPKG").CreateDataSource(frame)
            layer = ds.CreateLayer("frame", None, ogr.wkbPolygon)
            f = ogr.Feature(layer.GetLayerDefn())
            f.SetGeometry(ogr.CreateGeometryFromWkt("POLYGON((0 0,1024 0,1024 -1024,0 -1024,0 0))"))
            layer.CreateFeature(f)
            ds = None
        out = os.path.join(self.tmp, "footprint-%s.gpkg" % image)
        self.qgis("run", "geostation:monoplot", "--", "BLOCK=" + self.block, "IMAGE=" + image, "DEM=" + os.path.join(self.strip, "terrain.tif"),
                  "INPUT=" + frame, "DENSIFY_PX=64", "OUTPUT=" + out)
        ds = ogr.Open(out)
        feature = ds.GetLayer(0).GetNextFeature()
        return feature.GetGeometryRef().Clone()

    def assertRunSucceeded(self, done):
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)

    def report(self, output):
        with open(os.path.join(output + ".work", "run-report.json")) as f:
            return json.load(f)

    def features(self, path):
        """Each feature's id, attributes and geometry (WKT, 3 decimals), in the layer's order."""
        ds = ogr.Open(path)
        rows = []
        for f in ds.GetLayer(0):
            g = f.GetGeometryRef()
            rows.append((f.GetFID(), f.items(), g.ExportToIsoWkt() if g else None))
        return rows

    # ---------------------------------------------------------------------------------------------------------------

    def test_1_a_strip_is_one_network(self):
        out, done = self.extract("undisturbed")
        self.assertRunSucceeded(done)
        self.__class__.undisturbed = out
        report = self.report(out)
        self.assertEqual((report["units"], report["units_done"], report["units_failed"], report["workers"]), (4, 4, 0, 2), report)
        merged = [pts for pts, _ in bs.read_lines(out)]
        # the roads' centre lines (the layer also holds their edges, kerbs and markings, which are no roads of their own)
        truth = [pts for pts, items in bs.read_lines(os.path.join(self.strip, "truth.gpkg"), "roads") if items["kind"] == "centre"]
        doubled = bs.doubled_share(merged)
        print("merged network: %d lines, %.1f %% of its length doubled; merge: %s" % (len(merged), 100 * doubled, report["merge"]))
        self.assertLess(doubled, 0.02)
        # the measure sees a road twice: the pairs' lines side by side, unmerged
        unmerged = [pts for unit in sorted(os.listdir(os.path.join(out + ".work", "units")))
                    for pts, _ in bs.read_lines(os.path.join(out + ".work", "units", unit, unit[len("pair-"):] + ".gpkg"))]
        self.assertGreater(bs.doubled_share(unmerged), 0.05)
        # each pair against the truth where both its images see the ground, and the merged network where any pair does:
        # the merge finds at least what the pair finds there, and adds no wrong line of its own - its wrong length there
        # is at most that of all the pairs' lines side by side (a neighbouring pair's wrong lines are its own)
        images = ["S0001", "S0002", "S0003", "S0004", "S0005"]
        prints = {im: self.footprint(im) for im in images}
        pair_areas = []
        merged_everywhere = True
        for a, b in zip(images, images[1:]):
            area = prints[a].Intersection(prints[b]).Buffer(-20.0)
            pair_areas.append(area)
            own = [pts for pts, _ in bs.read_lines(os.path.join(out + ".work", "units", "pair-%s-%s" % (a, b), "%s-%s.gpkg" % (a, b)))]
            alone = bs.buffer_score(own, truth, BUFFER_M, bs.polygon_mask([area]))
            together = bs.buffer_score(merged, truth, BUFFER_M, bs.polygon_mask([area]))
            side_by_side = bs.buffer_score(unmerged, truth, BUFFER_M, bs.polygon_mask([area]))
            wrong_merged, wrong_side_by_side = (1 - together[1]) * together[3], (1 - side_by_side[1]) * side_by_side[3]
            print("pair %s-%s where it sees: completeness %.2f alone, %.2f merged; correctness %.2f alone, %.2f merged; "
                  "wrong length merged %.0f m, of all pairs' lines side by side %.0f m" %
                  (a, b, alone[0], together[0], alone[1], together[1], wrong_merged, wrong_side_by_side))
            # (completeness: lines are cut at pair borders, and where two pairs' lines repeat each other the first pair's is
            # kept, which may lie farther from the centre line than the other: S0004-S0005 loses 9 of its 172 m found so,
            # the line kept there 3.3-4 m off the centre line where its own was 0.2-3 m)
            merged_everywhere = merged_everywhere and together[0] >= alone[0] - 0.04 and wrong_merged <= 1.02 * wrong_side_by_side + 2
        strip = bs.buffer_score(merged, truth, BUFFER_M, bs.polygon_mask(pair_areas))
        print("merged network over the strip: completeness %.2f, correctness %.2f" % strip[:2])
        self.assertTrue(merged_everywhere, "the merged network finds less than a pair on its own where that pair sees, or adds wrong lines")

    def test_2_a_worker_killed_mid_run_loses_nothing(self):
        log = open(os.path.join(self.tmp, "killed.log"), "w")
        out, running = self.extract("killed", "--unit-timeout", "600", wait=False, log=log)
        manifest = os.path.join(out + ".work", "manifest")
        # as soon as a unit is done, one worker dies (with what it is running)
        for _ in range(600):
            if os.path.isdir(manifest) and os.listdir(manifest):
                break
            time.sleep(0.1)
        self.cluster.kill_worker(self.cluster.workers[0])
        status = running.wait(timeout=900)
        log.close()
        with open(os.path.join(self.tmp, "killed.log")) as f:
            self.assertEqual(status, 0, f.read())
        self.cluster.add_worker()
        self.cluster.wait_for_workers(2)
        self.assertEqual(self.report(out)["units_done"], 4)
        self.assertEqual(self.features(out), self.features(self.undisturbed))

    def test_3_a_unit_that_always_fails_is_named_and_the_rest_merged(self):
        broken = os.path.join(self.tmp, "broken")
        shutil.copytree(self.strip, broken)
        with open(os.path.join(broken, "images", "S0004.tif"), "wb") as f:
            f.write(b"not a TIFF" * 1000)
        out, done = self.extract("broken", "--retries", "1", block=os.path.join(broken, "block.geostation.json"))
        self.assertEqual(done.returncode, 3, done.stdout + done.stderr)
        report = self.report(out)
        failed = {f["id"]: f["error"] for f in report["failed"]}
        self.assertEqual(sorted(failed), ["pair-S0003-S0004", "pair-S0004-S0005"], report)
        for error in failed.values():
            self.assertIn("S0004", error)
        self.assertEqual(report["units_done"], 2)
        self.assertTrue(os.path.exists(out))
        self.assertIn("Failed: pair-S0003-S0004", done.stderr)
        pairs = {items["pairs"] for _, items in bs.read_lines(out)}
        self.assertTrue(all("S0004" not in p for p in pairs), pairs)

    def test_4_a_client_killed_and_started_again_runs_only_the_missing_units(self):
        log = open(os.path.join(self.tmp, "client.log"), "w")
        out, running = self.extract("resumed", wait=False, log=log)
        manifest = os.path.join(out + ".work", "manifest")
        for _ in range(600):
            if os.path.isdir(manifest) and os.listdir(manifest):
                break
            time.sleep(0.1)
        os.killpg(running.pid, 9)
        running.wait()
        log.close()
        time.sleep(3.0)  # what the scheduler still ran for the dead client is done or forgotten
        before = set(os.listdir(manifest))
        self.assertGreaterEqual(len(before), 1)
        out, done = self.extract("resumed")
        self.assertRunSucceeded(done)
        report = self.report(out)
        self.assertEqual(report["units_done"], 4)
        self.assertGreaterEqual(report["units_resumed"], len(before))
        self.assertEqual(report["units_run"], 4 - report["units_resumed"])
        self.assertEqual(self.features(out), self.features(self.undisturbed))

    def test_5_chunks_of_features_keep_ids_and_order(self):
        # the truth's roads as the map: projected into S0002 in chunks of 3 features, and at once
        roads = os.path.join(self.strip, "truth.gpkg") + "|layername=roads"
        whole = os.path.join(self.tmp, "projected-whole.gpkg")
        self.qgis("run", "geostation:project_to_image", "--", "BLOCK=" + self.block, "IMAGE=S0002", "INPUT=" + roads, "OUTPUT=" + whole)
        out = os.path.join(self.tmp, "projected", "roads-in-S0002.gpkg")
        done = bs.batch(self.home, "project", "--block", self.block, "--image", "S0002", "--input", roads, "--output", out,
                        "--unit-size", "3", "--scheduler", self.cluster.address)
        self.assertRunSucceeded(done)
        mine, theirs = self.features(out), self.features(whole)
        self.assertEqual(len(mine), len(theirs))
        truth = ogr.Open(os.path.join(self.strip, "truth.gpkg"))
        source = [f.GetFID() for f in truth.GetLayerByName("roads")]
        self.assertEqual([fid for fid, _, _ in mine], source)  # the input's ids, in its order
        self.assertEqual([(items, g) for _, items, g in mine], [(items, g) for _, items, g in theirs])
        self.assertGreaterEqual(self.report(out)["units"], 2)

    def trace_fixture(self):
        """A 200-station highway run (2 cameras, 960 x 540), the kerb's seeds at stations 1, 51, 101, 151, and one trace from the first."""
        if getattr(self.__class__, "run200", None):
            return self.__class__.run200
        run = os.path.join(self.tmp, "run200")
        self.qgis("run", "geostation:simulate_survey", "--", "PRESET=highway", "STATIONS=200", "SPACING=4", "CAMERAS=2", "IMAGE_WIDTH=960",
                  "IMAGE_HEIGHT=540", "OUTPUT_DIR=" + run)
        sys.path.insert(0, os.path.join(SOURCE_DIR, "scripts"))
        import demo_seeds
        rows = []
        for k, station in enumerate((1, 51, 101, 151)):
            one = os.path.join(self.tmp, "seed.csv")
            demo_seeds.main(run, "S%04d_FL" % station, "S%04d_FR" % station, one)
            with open(one, newline="") as f:
                kerb = next(r for r in csv.DictReader(f) if r["seed_id"] == "kerb")
            rows.append(dict(kerb, seed_id="kerb-%d" % (k + 1), line_id="kerb"))
        seeds = os.path.join(self.tmp, "seeds200.csv")
        with open(seeds, "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=["seed_id", "line_id", "image_id", "col", "row"])
            writer.writeheader()
            writer.writerows(rows)
        whole = os.path.join(self.tmp, "traced-whole.gpkg")
        with open(os.path.join(self.tmp, "seed1.csv"), "w", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=["seed_id", "line_id", "image_id", "col", "row"])
            writer.writeheader()
            writer.writerow(rows[0])
        self.qgis("run", "geostation:trace_road_lines", "--", "BLOCK=" + os.path.join(run, "block.geostation.json"), "SEEDS=" + os.path.join(self.tmp, "seed1.csv"),
                  "OUTPUT=" + whole)
        out = os.path.join(self.tmp, "traced", "kerb.gpkg")
        done = bs.batch(self.home, "trace", "--block", os.path.join(run, "block.geostation.json"), "--seeds", seeds, "--output", out,
                        "--scheduler", self.cluster.address)
        self.assertRunSucceeded(done)
        print(done.stderr.strip().splitlines()[-3:])
        self.__class__.run200 = (run, whole, out)
        return self.__class__.run200

    def kerb_lines(self, whole, out):
        def line(path):
            lines = bs.read_lines(path)
            self.assertEqual(len(lines), 1, path)
            return lines[0]
        return line(whole)[0], line(out)

    def test_7_a_run_traced_in_pieces_is_one_line(self):
        run, whole, out = self.trace_fixture()
        one, (pieces, items) = self.kerb_lines(whole, out)
        self.assertEqual((items["line_id"], items["pieces"]), ("kerb", 4))
        with open(os.path.join(out + ".work", "join-report.json")) as f:
            joined = json.load(f)
        self.assertEqual([d for d in joined["disagreements"] if d["gap"]], [])
        # the same as one trace where the pieces have settled onto it
        apart, _ = bs.distances(pieces, [one])
        print("kerb traced in 4 pieces: %d vertices, %.1f %% within 1 cm of one trace through the run, at most %.3f m from it" %
              (len(pieces), 100 * (apart <= 0.01).mean(), apart.max()))
        self.assertGreaterEqual((apart <= 0.01).mean(), 0.95)
        # and as close to the truth
        ds = ogr.Open(os.path.join(run, "truth.gpkg"))
        truth = []
        for f in ds.GetLayerByName("roads"):
            if f.GetField("id").startswith("R1-edge-right"):
                g = f.GetGeometryRef()
                truth.append(np.array([g.GetPoint(i)[:2] for i in range(g.GetPointCount())]))
        d_pieces, d_one = bs.distances(pieces, truth)[0], bs.distances(one, truth)[0]
        print("from the truth: pieces median %.3f, 95 %% %.3f m; one trace median %.3f, 95 %% %.3f m" %
              (np.median(d_pieces), np.percentile(d_pieces, 95), np.median(d_one), np.percentile(d_one, 95)))
        self.assertLessEqual(np.median(d_pieces), np.median(d_one) + 0.02)
        self.assertLessEqual(np.percentile(d_pieces, 95), np.percentile(d_one, 95) + 0.05)

    @unittest.expectedFailure
    def test_8_a_run_traced_in_pieces_equals_one_trace_within_a_centimetre(self):
        """Not yet: a trace depends on the stations before it. With the default overlap (100 stations) and the join at the last
        place two pieces agree, 99.6 % of the vertices are within 1 cm of one trace through the run, but a piece started from
        a later seed still strays from it by a few centimetres at scattered vertices long after it has settled (at most
        0.087 m here): the pieces never run as one trace everywhere."""
        run, whole, out = self.trace_fixture()
        one, (pieces, _) = self.kerb_lines(whole, out)
        self.assertLessEqual(bs.distances(pieces, [one])[0].max(), 0.01)

    def test_9_a_map_revised_over_a_strip_is_one_revision(self):
        """revise over the strip: each map road once, each stretch as confirmed as the pair that confirms it most."""
        # the map: the strip's road centre lines, the first moved 15 m north, the last left out (a new road), and a road that is not there
        ds = ogr.Open(os.path.join(self.strip, "truth.gpkg"))
        roads = ds.GetLayerByName("roads")
        centres = sorted((f.GetField("id"), f.GetGeometryRef().Clone()) for f in roads if re.match(r"R\d+-centre-\d+$", f.GetField("id")))
        self.assertGreaterEqual(len(centres), 3)
        map_path = os.path.join(self.tmp, "map.gpkg")
        out_ds = ogr.GetDriverByName("GPKG").CreateDataSource(map_path)
        layer = out_ds.CreateLayer("map", roads.GetSpatialRef(), ogr.wkbLineString)
        layer.CreateField(ogr.FieldDefn("name", ogr.OFTString))
        for k, (name, g) in enumerate(centres[:-1]):
            g.FlattenTo2D()
            if k == 0:
                for i in range(g.GetPointCount()):
                    g.SetPoint_2D(i, g.GetX(i), g.GetY(i) + 15.0)
            f = ogr.Feature(layer.GetLayerDefn())
            f.SetField("name", name + (" moved" if k == 0 else ""))
            f.SetGeometry(g)
            layer.CreateFeature(f)
        x0, y0 = centres[1][1].GetX(0), centres[1][1].GetY(0)
        f = ogr.Feature(layer.GetLayerDefn())
        f.SetField("name", "not there")
        f.SetGeometry(ogr.CreateGeometryFromWkt("LINESTRING (%f %f, %f %f)" % (x0 + 60, y0 + 200, x0 + 260, y0 + 230)))
        layer.CreateFeature(f)
        out_ds = None
        folder = os.path.join(self.tmp, "revised")
        os.makedirs(folder, exist_ok=True)
        out, new, vertices = (os.path.join(folder, n) for n in ("revised.gpkg", "new.gpkg", "vertices.gpkg"))
        done = bs.batch(self.home, "revise", "--block", self.block, "--map", map_path, "--output", out, "--new", new, "--vertices", vertices,
                        "--scheduler", self.cluster.address)
        self.assertRunSucceeded(done)
        report = self.report(out)
        self.assertEqual((report["units"], report["units_done"]), (4, 4), report)

        def stretches(path):
            lines, source = {}, ogr.Open(path)  # the data source held while its layer is read
            for f in source.GetLayer(0):
                lines.setdefault((f.GetField("source_fid"), f.GetField("map_part")), []).append(
                    (f.GetField("map_from_m"), f.GetField("map_to_m"), f.GetField("revision")))
            return {k: sorted(v) for k, v in lines.items()}

        merged = stretches(out)
        pairs = {u[len("pair-"):]: stretches(os.path.join(out + ".work", "units", u, u[len("pair-"):] + ".gpkg"))
                 for u in os.listdir(os.path.join(out + ".work", "units"))}
        self.assertEqual(len(pairs), 4)
        for road, line in merged.items():
            # the road once: its stretches follow one another from its start to its end
            ends = {own[road][-1][1] for own in pairs.values()}
            self.assertEqual(len(ends), 1, ends)
            self.assertAlmostEqual(line[0][0], 0.0, places=6)
            self.assertAlmostEqual(line[-1][1], ends.pop(), places=6)
            for (a, b, _), (c, d, _) in zip(line, line[1:]):
                self.assertAlmostEqual(b, c, places=6)
            # confirmed at least as far as the pair that confirms most of it
            confirmed = sum(b - a for a, b, r in line if r == "confirmed")
            best = max(sum(b - a for a, b, r in own[road] if r == "confirmed") for own in pairs.values())
            print("map road %s: %s; confirmed %.0f m merged, %.0f m by the best pair" %
                  (road, ", ".join("%.0f-%.0f %s" % s for s in line), confirmed, best))
            self.assertGreaterEqual(confirmed, best - 1e-6)
        merged_ds, vertices_ds = ogr.Open(out), ogr.Open(vertices)
        with_pairs = [f.GetField("pairs") for f in merged_ds.GetLayer(0)]
        self.assertTrue(all(p for p in with_pairs), with_pairs)
        self.assertGreater(vertices_ds.GetLayer(0).GetFeatureCount(), 0)
        # the road left out of the map is among the new roads
        left_out = [np.array([centres[-1][1].GetPoint(i)[:2] for i in range(centres[-1][1].GetPointCount())])]
        new_lines = [pts for pts, _ in bs.read_lines(new)]
        near = bs.distances(np.vstack(new_lines), left_out)[0] <= 3.0 if new_lines else np.zeros(0, dtype=bool)
        print("revise: %s; new roads %d lines, %.0f %% of their vertices on the road left out of the map" %
              (report["merge"], len(new_lines), 100 * near.mean() if len(near) else 0.0))
        self.assertGreater(near.sum(), 20)

    def test_6_bad_input_is_one_sentence(self):
        done = bs.batch(self.home, "extract", "--block", os.path.join(self.tmp, "none.json"), "--output",
                        os.path.join(self.tmp, "none", "roads.gpkg"), "--scheduler", self.cluster.address)
        self.assertEqual(done.returncode, 1, done.stdout + done.stderr)
        self.assertIn("none.json does not exist", done.stderr)
        done = bs.batch(self.home, "extract", "--block", self.block, "--output", os.path.join(self.tmp, "none", "roads.gpkg"),
                        "--scheduler", "tcp://127.0.0.1:9")
        self.assertEqual(done.returncode, 1, done.stdout + done.stderr)
        self.assertIn("no Dask scheduler answers", done.stderr)


if __name__ == "__main__":
    SOURCE_DIR, BUILD_DIR = sys.argv[1], sys.argv[2]
    unittest.main(argv=sys.argv[:1] + sys.argv[3:], verbosity=2)  # further arguments: the tests to run (as unittest takes them)
