"""The units of a command: stereo pairs of a block, chunks of features."""

import csv
import json
import math
import os

from osgeo import ogr

ogr.UseExceptions()

# the field a chunk carries the source feature's id in, through the algorithm, back to the merge
SOURCE_FID = "batch_source_fid"


class BadInput(Exception):
    """Input the batch cannot use: one sentence."""


def read_block(path):
    try:
        with open(path) as f:
            return json.load(f)
    except OSError as e:
        raise BadInput("cannot read the block %s: %s" % (path, e.strerror))
    except ValueError as e:
        raise BadInput("the block %s is not JSON: %s" % (path, e))


def _oriented(image):
    return all(k in image for k in ("X", "Y", "Z"))


def strip_pairs(block):
    """Overlapping images along each strip: neighbours in the block's order (by station time where the
    block has stations), of one camera, both oriented, no farther apart than 1.5 times the median step
    (a longer step starts a new strip)."""
    images = [im for im in block.get("images", []) if _oriented(im)]
    order = {s.get("id"): i for i, s in enumerate(block.get("stations", []))}
    images.sort(key=lambda im: (order.get(im.get("station"), len(order)), block["images"].index(im)))
    steps = []
    for a, b in zip(images, images[1:]):
        if a.get("camera") == b.get("camera"):
            steps.append(math.dist((a["X"], a["Y"], a["Z"]), (b["X"], b["Y"], b["Z"])))
    if not steps:
        return []
    median = sorted(steps)[len(steps) // 2]
    pairs = []
    for a, b in zip(images, images[1:]):
        if a.get("camera") == b.get("camera") and 0 < math.dist((a["X"], a["Y"], a["Z"]), (b["X"], b["Y"], b["Z"])) <= 1.5 * median:
            pairs.append((a["id"], b["id"]))
    return pairs


def table_pairs(path, block):
    """The pairs of a PAIRS table (CSV or any table OGR reads; fields left, right)."""
    rows = [(r.get("left", "").strip(), r.get("right", "").strip()) for r in read_table(path, "pairs")]
    ids = {im["id"] for im in block.get("images", [])}
    for left, right in rows:
        if not left or not right:
            raise BadInput("the pairs %s need the fields left and right, filled in every row" % path)
        for image in (left, right):
            if image not in ids:
                raise BadInput("the pairs %s name image %s, which the block does not hold" % (path, image))
        if left == right:
            raise BadInput("the pairs %s pair %s with itself" % (path, left))
    return rows


def pair_name(left, right):
    return "%s-%s" % (left, right)


def feature_count(path):
    ds = _open_vector(path)
    return ds.GetLayer(0).GetFeatureCount()


def _open_vector(path):
    layer_name = None
    if "|layername=" in path:
        path, layer_name = path.split("|layername=", 1)
    try:
        ds = ogr.Open(path)
    except RuntimeError:
        ds = None
    if ds is None:
        raise BadInput("cannot read the layer %s" % path)
    if layer_name is not None:
        # a dataset of that one layer, so GetLayer(0) is it
        layer = ds.GetLayerByName(layer_name)
        if layer is None:
            raise BadInput("%s has no layer %s" % (path, layer_name))
        mem = ogr.GetDriverByName("Memory").CreateDataSource("")
        mem.CopyLayer(layer, layer_name)
        return mem
    return ds


def write_chunks(path, unit_size, folder):
    """The features of a layer in chunks of `unit_size`, each a GeoPackage with the source's fields
    and its feature id in SOURCE_FID; returns the chunk files in order."""
    ds = _open_vector(path)
    source = ds.GetLayer(0)
    if source.GetLayerDefn().GetFieldIndex(SOURCE_FID) >= 0:
        raise BadInput("the input has a field named %s, which the batch adds: rename it" % SOURCE_FID)
    os.makedirs(folder, exist_ok=True)
    driver = ogr.GetDriverByName("GPKG")
    chunks, out, layer, n = [], None, None, 0
    source.ResetReading()
    for feature in source:
        if n % unit_size == 0:
            out = None  # closes the previous chunk
            chunk = os.path.join(folder, "chunk-%05d.gpkg" % len(chunks))
            if os.path.exists(chunk):
                driver.DeleteDataSource(chunk)
            out = driver.CreateDataSource(chunk)
            layer = out.CreateLayer("features", source.GetSpatialRef(), source.GetGeomType())
            for i in range(source.GetLayerDefn().GetFieldCount()):
                layer.CreateField(source.GetLayerDefn().GetFieldDefn(i))
            layer.CreateField(ogr.FieldDefn(SOURCE_FID, ogr.OFTInteger64))
            layer.StartTransaction()
            chunks.append(chunk)
        copy = ogr.Feature(layer.GetLayerDefn())
        for i in range(source.GetLayerDefn().GetFieldCount()):
            copy.SetField(i, feature.GetField(i))
        copy.SetField(SOURCE_FID, feature.GetFID())
        copy.SetGeometry(feature.GetGeometryRef())
        layer.CreateFeature(copy)
        n += 1
        if n % unit_size == 0:
            layer.CommitTransaction()
    if layer is not None and n % unit_size != 0:
        layer.CommitTransaction()
    out = None
    return chunks


def read_table(path, what):
    """The rows of a table (CSV, or any table OGR reads) as dicts of text; `what` names it in a message."""
    if path.lower().endswith(".csv"):
        try:
            with open(path, newline="") as f:
                return [dict(r) for r in csv.DictReader(f)]
        except OSError as e:
            raise BadInput("cannot read the %s %s: %s" % (what, path, e.strerror))
    ds = _open_vector(path)
    layer = ds.GetLayer(0)
    return [{k: ("" if v is None else str(v)) for k, v in f.items().items()} for f in layer]


def seed_pieces(rows, block, max_stations, overlap_stations):
    """The seeds of each line (`line_id`, else each seed its own line) in the order of their stations along
    the run, each with the stations it traces: up to the next seed's station plus `overlap_stations`, the
    last one `max_stations` (0: to the end of the run). Returns [(line_id, order, seed row, stations)]."""
    stations = {s.get("id"): i for i, s in enumerate(block.get("stations", []))}
    images = {im["id"]: im for im in block.get("images", [])}
    lines = {}
    for row in rows:
        seed_id, image_id = row.get("seed_id", "").strip(), row.get("image_id", "").strip()
        if not seed_id or not image_id:
            raise BadInput("every seed needs a seed_id and an image_id")
        if image_id not in images:
            raise BadInput("seed %s is in image %s, which the block does not hold" % (seed_id, image_id))
        station = stations.get(images[image_id].get("station"))
        if station is None:
            raise BadInput("seed %s is in image %s, which belongs to no station of the block's run" % (seed_id, image_id))
        lines.setdefault((row.get("line_id") or "").strip() or seed_id, []).append((station, seed_id, row))
    pieces = []
    for line_id in sorted(lines):
        seeds = sorted(lines[line_id], key=lambda s: (s[0], s[1]))
        for k, (station, seed_id, row) in enumerate(seeds):
            if k > 0 and station == seeds[k - 1][0]:
                raise BadInput("line %s has two seeds at one station (%s and %s)" % (line_id, seeds[k - 1][1], seed_id))
            count = seeds[k + 1][0] - station + 1 + overlap_stations if k + 1 < len(seeds) else max_stations
            pieces.append((line_id, k + 1, row, count))
    return pieces
