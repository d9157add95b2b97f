"""Merges, each deterministic: units are taken in the order of their ids, never
in the order they finished, and every output is written beside its final
place and moved there in one rename (a failed merge leaves no file)."""

import json
import os
import shutil
import tempfile

from osgeo import ogr

from . import plan, qgis

ogr.UseExceptions()

DRIVERS = {".gpkg": "GPKG", ".shp": "ESRI Shapefile", ".geojson": "GeoJSON", ".json": "GeoJSON", ".csv": "CSV", ".fgb": "FlatGeobuf"}


class MergeFailed(Exception):
    """The merge could not be written: one sentence."""


def _staged(output):
    """A folder beside `output` to write it in first (same file system, so the move is a rename)."""
    folder = os.path.dirname(os.path.abspath(output))
    os.makedirs(folder, exist_ok=True)
    return tempfile.mkdtemp(dir=folder, prefix=".geostation-batch-")


def _move_into_place(staged_file, output):
    """Moves the staged file (and a Shapefile's sidecars) to `output`."""
    base, ext = os.path.splitext(staged_file)
    out_base, _ = os.path.splitext(os.path.abspath(output))
    if ext.lower() == ".shp":
        for side in os.listdir(os.path.dirname(staged_file)):
            s_base, s_ext = os.path.splitext(side)
            if s_base == os.path.basename(base):
                os.replace(os.path.join(os.path.dirname(staged_file), side), out_base + s_ext)
    else:
        os.replace(staged_file, os.path.abspath(output))


def _run_into_place(algorithm, inputs, output, executable, qgis_home, staging, what, report_path=None, more_outputs=None):
    """Runs a merging algorithm into `staging`, moves its OUTPUT to `output` (and each of `more_outputs`, name -> path,
    to its path) and returns its REPORT (copied to `report_path`)."""
    home = qgis.private_home(qgis_home, os.path.join(staging, "home"))
    staged = os.path.join(staging, os.path.basename(output))
    staged_report = os.path.join(staging, "report.json")
    more = {name: os.path.join(staging, name.lower(), os.path.basename(path)) for name, path in (more_outputs or {}).items()}
    for path in more.values():
        os.makedirs(os.path.dirname(path), exist_ok=True)
    code, out, err = qgis.run(executable, home, algorithm, dict(inputs, OUTPUT=staged, REPORT=staged_report, **more))
    if code != 0:
        raise MergeFailed("%s failed: %s" % (what, qgis.failure_sentence(code, out, err)))
    with open(staged_report) as f:
        report = json.load(f)
    for name, path in (more_outputs or {}).items():
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        _move_into_place(more[name], path)
    _move_into_place(staged, output)
    if report_path:
        shutil.copyfile(staged_report, report_path)
    return report


def road_networks(unit_outputs, output, executable, qgis_home, report_path=None):
    """geostation:merge_road_networks over the pairs' networks (in the order of the pairs); returns its report."""
    staging = _staged(output)
    try:
        inputs = {"INPUTS": sorted(unit_outputs, key=lambda p: os.path.basename(p))}
        return _run_into_place("geostation:merge_road_networks", inputs, output, executable, qgis_home, staging, "merging the road networks", report_path)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def revisions(unit_outputs, unit_vertices, output, vertices_output, executable, qgis_home, report_path=None):
    """geostation:merge_revisions over the pairs' revisions and vertex tables (in the order of the pairs); returns its report."""
    staging = _staged(output)
    try:
        pairs = sorted(zip(unit_outputs, unit_vertices), key=lambda p: os.path.basename(p[0]))
        inputs = {"INPUTS": [p[0] for p in pairs], "VERTICES": [p[1] for p in pairs]}
        return _run_into_place("geostation:merge_revisions", inputs, output, executable, qgis_home, staging, "merging the revisions", report_path,
                               {"VERTICES_OUTPUT": vertices_output} if vertices_output else None)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def feature_chunks(chunk_outputs, output):
    """The chunks' outputs as one layer, in chunk order, each feature with the id it had in the input
    (GeoPackage; other formats number their own) and without the batch's field. Returns the count."""
    ext = os.path.splitext(output)[1].lower()
    driver_name = DRIVERS.get(ext)
    if driver_name is None:
        raise MergeFailed("cannot write %s: give an output ending in %s" % (output, ", ".join(sorted(DRIVERS))))
    staging = _staged(output)
    try:
        staged = os.path.join(staging, os.path.basename(output))
        ds_out = ogr.GetDriverByName(driver_name).CreateDataSource(staged)
        layer_out, keep, count = None, [], 0
        for chunk in chunk_outputs:
            ds = ogr.Open(chunk)
            source = ds.GetLayer(0)
            definition = source.GetLayerDefn()
            if layer_out is None:
                name = os.path.splitext(os.path.basename(output))[0]
                layer_out = ds_out.CreateLayer(name, source.GetSpatialRef(), source.GetGeomType())
                for i in range(definition.GetFieldCount()):
                    if definition.GetFieldDefn(i).GetName() != plan.SOURCE_FID:
                        layer_out.CreateField(definition.GetFieldDefn(i))
                        keep.append(definition.GetFieldDefn(i).GetName())
                layer_out.StartTransaction()
            source_fid = definition.GetFieldIndex(plan.SOURCE_FID)
            if source_fid < 0:
                raise MergeFailed("%s lost the field %s: the algorithm did not carry the input's attributes" % (chunk, plan.SOURCE_FID))
            for feature in source:
                copy = ogr.Feature(layer_out.GetLayerDefn())
                for name in keep:
                    copy.SetField(name, feature.GetField(name))
                copy.SetGeometry(feature.GetGeometryRef())
                copy.SetFID(feature.GetFieldAsInteger64(source_fid))
                layer_out.CreateFeature(copy)
                count += 1
            ds = None
        if layer_out is not None:
            layer_out.CommitTransaction()
        ds_out = None
        if layer_out is None:
            raise MergeFailed("no unit wrote any feature")
        _move_into_place(staged, output)
        return count
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def traced_pieces(pieces, output, executable, qgis_home, work_dir, report_path=None):
    """The pieces traced from each seed joined per line (geostation:join_traced_pieces).

    `pieces`: [(line_id, order, seed_id, unit output)] in any order; returns the join's report."""
    staging = _staged(output)
    try:
        table = os.path.join(staging, "pieces.gpkg")
        ds_out = ogr.GetDriverByName("GPKG").CreateDataSource(table)
        layer_out = None
        for line_id, order, seed_id, path in sorted(pieces):
            ds = ogr.Open(path)
            source = ds.GetLayer(0)
            if layer_out is None:
                layer_out = ds_out.CreateLayer("pieces", source.GetSpatialRef(), ogr.wkbLineString25D)
                for name, kind in (("line_id", ogr.OFTString), ("piece", ogr.OFTInteger), ("seed_id", ogr.OFTString), ("sigma_max", ogr.OFTReal)):
                    layer_out.CreateField(ogr.FieldDefn(name, kind))
            for feature in source:
                if feature.GetGeometryRef() is None:
                    continue
                copy = ogr.Feature(layer_out.GetLayerDefn())
                copy.SetField("line_id", line_id)
                copy.SetField("piece", order)
                copy.SetField("seed_id", seed_id)
                if feature.GetFieldIndex("sigma_max") >= 0 and feature.IsFieldSetAndNotNull("sigma_max"):
                    copy.SetField("sigma_max", feature.GetField("sigma_max"))
                copy.SetGeometry(feature.GetGeometryRef())
                layer_out.CreateFeature(copy)
            ds = None
        ds_out = None
        if layer_out is None:
            raise MergeFailed("no unit traced anything")
        report = _run_into_place("geostation:join_traced_pieces", {"INPUT": table}, output, executable, qgis_home, staging,
                                 "joining the traced pieces", report_path)
        shutil.copyfile(table, os.path.join(work_dir, "pieces.gpkg"))
        return report
    finally:
        shutil.rmtree(staging, ignore_errors=True)
