"""An independent reference implementation of docs/conventions.md §1-3 in numpy.

Written from the conventions text, not from the C++ code, so that end-to-end
tests compare GeoStation's output against numbers computed another way (the
brown_photo inverse uses fixed-point iteration, not Newton's method).
"""

import math

import numpy as np


def rotation(omega_deg, phi_deg, kappa_deg):
    """R = Rx(omega) Ry(phi) Rz(kappa), camera -> object."""
    w, p, k = (math.radians(a) for a in (omega_deg, phi_deg, kappa_deg))
    rx = np.array([[1, 0, 0], [0, math.cos(w), -math.sin(w)], [0, math.sin(w), math.cos(w)]])
    ry = np.array([[math.cos(p), 0, math.sin(p)], [0, 1, 0], [-math.sin(p), 0, math.cos(p)]])
    rz = np.array([[math.cos(k), -math.sin(k), 0], [math.sin(k), math.cos(k), 0], [0, 0, 1]])
    return rx @ ry @ rz


def project(camera, image, ground):
    """(col, row) of a ground point, or None when it is behind the camera or
    beyond the lens model's field (twice the frame-corner radius)."""
    R = rotation(image["omega"], image["phi"], image["kappa"])
    p = R.T @ (np.asarray(ground, float) - np.array([image["X"], image["Y"], image["Z"]]))
    if p[2] >= 0:
        return None
    f, cx, cy = camera["f"], camera["cx"], camera["cy"]
    aspect = camera.get("aspect", 1.0)
    d = camera.get("distortion", {"model": "none"})
    k1, k2, k3, p1, p2 = (d.get(n, 0.0) for n in ("k1", "k2", "k3", "p1", "p2"))
    xn, yn = -p[0] / p[2], -p[1] / p[2]          # ideal, y up
    if d["model"] != "none":
        # GeoStation trusts a lens model out to twice the frame-corner radius.
        corner = max(math.hypot((u - cx) / f, (v - cy) / (f * aspect))
                     for u in (0, camera["width"]) for v in (0, camera["height"]))
        if math.hypot(xn, yn) > 2 * corner:
            return None
    if d["model"] == "none":
        return cx + f * xn, cy - f * aspect * yn
    if d["model"] == "opencv":
        x, y = xn, -yn                            # OpenCV frame: y down
        r2 = x * x + y * y
        radial = 1 + k1 * r2 + k2 * r2 ** 2 + k3 * r2 ** 3
        xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
        yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
        return cx + f * xd, cy + f * aspect * yd
    if d["model"] == "brown_photo":
        ps = camera["pixel_size_mm"]
        c = f * ps
        ideal = np.array([c * xn, c * yn])
        xb, yb = ideal
        for _ in range(200):                      # measured + correction(measured) = ideal
            r2 = xb * xb + yb * yb
            radial = k1 * r2 + k2 * r2 ** 2 + k3 * r2 ** 3
            dx = xb * radial + p1 * (r2 + 2 * xb * xb) + 2 * p2 * xb * yb
            dy = yb * radial + 2 * p1 * xb * yb + p2 * (r2 + 2 * yb * yb)
            xb, yb = ideal[0] - dx, ideal[1] - dy
        return cx + xb / ps, cy - yb * aspect / ps
    raise ValueError("unknown distortion model " + d["model"])
