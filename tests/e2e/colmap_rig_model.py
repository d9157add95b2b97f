"""Writes a GeoStation block's run as a COLMAP 3.12 text model with rigs and
frames (the layout of COLMAP's reconstruction_io_text.cc): the cameras with
the "opencv" lens model as OPENCV cameras, their images, one rig of those
cameras (the first the reference) and one frame per station. Used by the
end-to-end tests of the import in QGIS."""

import json
import math
import os

import numpy as np

from conventions_reference import rotation  # R = Rx(omega) Ry(phi) Rz(kappa), camera -> world


def quaternion(r):
    """(w, x, y, z) of a rotation matrix."""
    w = math.sqrt(max(0.0, 1.0 + r[0, 0] + r[1, 1] + r[2, 2])) / 2.0
    x = math.copysign(math.sqrt(max(0.0, 1.0 + r[0, 0] - r[1, 1] - r[2, 2])) / 2.0, r[2, 1] - r[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1.0 - r[0, 0] + r[1, 1] - r[2, 2])) / 2.0, r[0, 2] - r[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1.0 - r[0, 0] - r[1, 1] + r[2, 2])) / 2.0, r[1, 0] - r[0, 1])
    return w, x, y, z


def pose_text(r, t):
    return " ".join(repr(float(v)) for v in (*quaternion(r), *t))


def write_rig_model(block_path, model_dir):
    """Returns the number of frames written. COLMAP's image names are the
    block's image paths relative to its `images` folder."""
    with open(block_path) as f:
        block = json.load(f)
    cameras = [c for c in block["cameras"] if c.get("distortion", {}).get("model") == "opencv"]
    camera_number = {c["id"]: i + 1 for i, c in enumerate(cameras)}
    flip = np.diag([1.0, -1.0, -1.0])  # COLMAP's camera: y down, z forward
    os.makedirs(model_dir, exist_ok=True)
    with open(os.path.join(model_dir, "cameras.txt"), "w") as out:
        for c in cameras:
            d = c["distortion"]
            params = (c["f"], c["f"] * c.get("aspect", 1.0), c["cx"], c["cy"], d["k1"], d["k2"], d["p1"], d["p2"])
            out.write("%d OPENCV %d %d %s\n" % (camera_number[c["id"]], c["width"], c["height"], " ".join(repr(float(p)) for p in params)))
    poses, frames = {}, {}
    with open(os.path.join(model_dir, "images.txt"), "w") as out:
        for n, image in enumerate(block["images"], start=1):
            if image["camera"] not in camera_number:
                continue
            cam_from_world = flip @ rotation(image["omega"], image["phi"], image["kappa"]).T
            t = -cam_from_world @ np.array([image["X"], image["Y"], image["Z"]])
            poses[n] = (cam_from_world, t)
            frames.setdefault(image["station"], []).append((camera_number[image["camera"]], n))
            name = os.path.relpath(image["path"], "images")
            out.write("%d %s %d %s\n\n" % (n, pose_text(cam_from_world, t), camera_number[image["camera"]], name))
    stations = sorted(frames)
    first = dict(frames[stations[0]])
    reference = poses[first[1]]
    with open(os.path.join(model_dir, "rigs.txt"), "w") as out:
        sensors = ["CAMERA 1"]
        for camera in range(2, len(cameras) + 1):
            r = poses[first[camera]][0] @ reference[0].T
            t = poses[first[camera]][1] - r @ reference[1]
            sensors.append("CAMERA %d 1 %s" % (camera, pose_text(r, t)))
        out.write("1 %d %s\n" % (len(cameras), " ".join(sensors)))
    with open(os.path.join(model_dir, "frames.txt"), "w") as out:
        for number, station in enumerate(stations, start=1):
            members = sorted(frames[station])
            rig_from_world = poses[dict(members)[1]]
            out.write("%d 1 %s %d %s\n" % (number, pose_text(*rig_from_world), len(members),
                                          " ".join("CAMERA %d %d" % m for m in members)))
    return len(stations)
