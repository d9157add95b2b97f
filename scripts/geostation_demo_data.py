#!/usr/bin/python3
"""Writes a small GeoStation demo block: a van run with three cameras.

    scripts/geostation_demo_data.py OUTPUT_DIR [--stations N] [--seed S]

OUTPUT_DIR receives:
  block.geostation.json   the block (EPSG:32617, exact orientation, GNSS/INS sigmas)
  images/                 one 640 x 480 GeoTIFF per image (textured placeholders)
  objects.gpkg            layer "objects": PointZ poles and hydrants (id, kind)

The geometry is exact; the imagery is a placeholder texture until the survey
simulator renders real scenes. Uses GDAL's Python bindings and numpy.
"""

import argparse
import json
import math
import os
import sys

import numpy as np
from osgeo import gdal, ogr, osr

CRS = "EPSG:32617"
GROUND_Z = 100.0          # flat road surface, metres
CAMERA_HEIGHT = 2.6       # above the road
START = np.array([500000.0, 4400000.0])
STATION_SPACING = 5.0     # metres along the run

CAMERAS = [
    {"id": "front_left", "width": 640, "height": 480, "f": 560.0, "aspect": 1.0, "cx": 321.2, "cy": 239.4,
     "pixel_size_mm": 0.0098, "distortion": {"model": "opencv", "k1": -0.21, "k2": 0.05, "p1": 0.0006, "p2": -0.0004, "k3": 0.0}},
    {"id": "front_right", "width": 640, "height": 480, "f": 558.5, "aspect": 1.0, "cx": 318.7, "cy": 241.1,
     "pixel_size_mm": 0.0098, "distortion": {"model": "opencv", "k1": -0.19, "k2": 0.04, "p1": -0.0003, "p2": 0.0002, "k3": 0.0}},
    {"id": "side_right", "width": 640, "height": 480, "f": 700.0, "aspect": 1.0, "cx": 320.0, "cy": 240.0,
     "pixel_size_mm": 0.0098, "distortion": {"model": "brown_photo", "k1": 2.0e-3, "k2": -1.0e-5, "p1": 1.0e-5, "p2": -2.0e-5, "k3": 0.0}},
]
# Mounting on the van: offset (right, forward, up) in metres and the viewing
# direction as (yaw to the right of the heading, pitch down), degrees.
MOUNTS = {
    "front_left": ((-1.0, 0.5, CAMERA_HEIGHT), (-12.0, 8.0)),
    "front_right": ((1.0, 0.5, CAMERA_HEIGHT), (12.0, 8.0)),
    "side_right": ((1.0, 0.0, CAMERA_HEIGHT), (90.0, 10.0)),
}


def heading_at(s):
    """Heading of the run (radians, clockwise from north) at distance s: a gentle curve."""
    return math.radians(8.0) * math.sin(s / 40.0)


def centre_line(n_points, step):
    """Positions and headings of the road centre every `step` metres."""
    xy = [START.copy()]
    headings = [heading_at(0.0)]
    for i in range(1, n_points):
        h = heading_at((i - 0.5) * step)
        xy.append(xy[-1] + step * np.array([math.sin(h), math.cos(h)]))
        headings.append(heading_at(i * step))
    return np.array(xy), np.array(headings)


def world_from_camera(heading, yaw, pitch_down):
    """Rotation whose columns are the camera's x (right), y (up), z (backwards) in the world."""
    az = heading + math.radians(yaw)
    forward = np.array([math.sin(az) * math.cos(math.radians(pitch_down)),
                        math.cos(az) * math.cos(math.radians(pitch_down)),
                        -math.sin(math.radians(pitch_down))])
    right = np.cross(forward, [0.0, 0.0, 1.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    return np.column_stack([right, up, -forward])


def omega_phi_kappa(R):
    """Degrees, for R = Rx(omega) Ry(phi) Rz(kappa)."""
    phi = math.asin(max(-1.0, min(1.0, R[0, 2])))
    omega = math.atan2(-R[1, 2], R[2, 2])
    kappa = math.atan2(-R[0, 1], R[0, 0])
    return math.degrees(omega), math.degrees(phi), math.degrees(kappa)


def write_texture(path, width, height, rng):
    """A grey, asphalt-like texture so the images are not blank."""
    noise = rng.normal(0.0, 1.0, (height // 4 + 1, width // 4 + 1))
    coarse = np.kron(noise, np.ones((4, 4)))[:height, :width]
    fine = rng.normal(0.0, 1.0, (height, width))
    ramp = np.linspace(150, 90, height)[:, None]
    image = np.clip(ramp + 18.0 * coarse + 8.0 * fine, 0, 255).astype(np.uint8)
    driver = gdal.GetDriverByName("GTiff")
    ds = driver.Create(path, width, height, 1, gdal.GDT_Byte, ["COMPRESS=DEFLATE"])
    ds.GetRasterBand(1).WriteArray(image)
    ds = None


def write_objects(path, positions, headings, rng):
    srs = osr.SpatialReference()
    srs.SetFromUserInput(CRS)
    if os.path.exists(path):
        os.remove(path)
    ds = ogr.GetDriverByName("GPKG").CreateDataSource(path)
    layer = ds.CreateLayer("objects", srs, ogr.wkbPoint25D)
    layer.CreateField(ogr.FieldDefn("id", ogr.OFTString))
    layer.CreateField(ogr.FieldDefn("kind", ogr.OFTString))
    count = 0
    for i in range(0, len(positions), 2):
        h = headings[i]
        right = np.array([math.cos(h), -math.sin(h)])
        for side, kind in ((1, "pole"), (-1, "hydrant")):
            offset = side * (5.5 + rng.uniform(-0.5, 0.5))
            p = positions[i] + offset * right
            for z, suffix in ((GROUND_Z, "foot"), (GROUND_Z + (6.0 if kind == "pole" else 0.8), "top")):
                f = ogr.Feature(layer.GetLayerDefn())
                f.SetField("id", "%s_%03d_%s" % (kind, i, suffix))
                f.SetField("kind", kind)
                f.SetGeometry(ogr.CreateGeometryFromWkt("POINT Z (%.4f %.4f %.4f)" % (p[0], p[1], z)))
                layer.CreateFeature(f)
                count += 1
    ds = None
    return count


def make_demo_block(output_dir, stations=8, seed=1):
    rng = np.random.default_rng(seed)
    os.makedirs(os.path.join(output_dir, "images"), exist_ok=True)
    positions, headings = centre_line(stations + 4, STATION_SPACING)
    block = {"format": "geostation-block", "version": 1, "crs": CRS,
             "cameras": CAMERAS, "stations": [], "images": []}
    for i in range(stations):
        station_id = "S%04d" % (i + 1)
        seconds = i * 0.7
        block["stations"].append({"id": station_id, "time": "2025-05-01T10:00:%06.3fZ" % seconds,
                                  "trajectory": "P-line 1"})
        h = headings[i]
        right = np.array([math.cos(h), -math.sin(h), 0.0])
        forward = np.array([math.sin(h), math.cos(h), 0.0])
        base = np.array([positions[i][0], positions[i][1], GROUND_Z])
        for camera in CAMERAS:
            (dr, df, dz), (yaw, pitch) = MOUNTS[camera["id"]]
            centre = base + dr * right + df * forward + np.array([0.0, 0.0, dz])
            omega, phi, kappa = omega_phi_kappa(world_from_camera(h, yaw, pitch))
            image_id = "%s_%s" % (station_id, camera["id"])
            path = "images/%s.tif" % image_id
            write_texture(os.path.join(output_dir, path), camera["width"], camera["height"], rng)
            block["images"].append({
                "id": image_id, "camera": camera["id"], "station": station_id, "path": path,
                "X": round(centre[0], 4), "Y": round(centre[1], 4), "Z": round(centre[2], 4),
                "omega": round(omega, 6), "phi": round(phi, 6), "kappa": round(kappa, 6),
                "sigma": {"X": 0.05, "Y": 0.05, "Z": 0.08, "omega": 0.01, "phi": 0.01, "kappa": 0.02}})
    block_path = os.path.join(output_dir, "block.geostation.json")
    with open(block_path, "w") as out:
        json.dump(block, out, indent=2)
    n_objects = write_objects(os.path.join(output_dir, "objects.gpkg"), positions, headings, rng)
    return block_path, n_objects


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output_dir")
    parser.add_argument("--stations", type=int, default=8)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args(argv)
    if args.stations < 1:
        parser.error("--stations must be at least 1")
    gdal.UseExceptions()
    block_path, n_objects = make_demo_block(args.output_dir, args.stations, args.seed)
    print("wrote %s (%d stations x %d cameras) and %d objects" % (block_path, args.stations, len(CAMERAS), n_objects))


if __name__ == "__main__":
    main(sys.argv[1:])
