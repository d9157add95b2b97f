"""What the batch tests share: a real Dask cluster on the loopback interface
(a dask-scheduler and dask-worker processes, started and stopped by the
test), the batch command run as a user runs it, and line scoring by the
buffer method against the simulator's truth."""

import json
import os
import signal
import subprocess
import time

import numpy as np
from osgeo import ogr

ogr.UseExceptions()


class LoopbackCluster:
    """dask-scheduler and `workers` dask-worker processes (one thread each, no nanny: a killed worker stays dead).

    The workers get no Python path of GeoStation's: what a unit runs travels with it, as on a cluster's nodes."""

    def __init__(self, folder, workers):
        self.folder = folder
        os.makedirs(folder, exist_ok=True)
        self.scheduler_file = os.path.join(folder, "scheduler.json")
        self.env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
        self.log = open(os.path.join(folder, "cluster.log"), "a")
        self.scheduler = subprocess.Popen(["dask-scheduler", "--host", "127.0.0.1", "--port", "0", "--dashboard-address", ":0",
                                           "--scheduler-file", self.scheduler_file], env=self.env, stdout=self.log, stderr=self.log,
                                          start_new_session=True)
        for _ in range(300):
            if os.path.exists(self.scheduler_file) and os.path.getsize(self.scheduler_file) > 0:
                break
            time.sleep(0.1)
        with open(self.scheduler_file) as f:
            self.address = json.load(f)["address"]
        self.workers = []
        for _ in range(workers):
            self.add_worker()
        self.wait_for_workers(workers)

    def add_worker(self):
        worker = subprocess.Popen(["dask-worker", self.address, "--nthreads", "1", "--no-nanny", "--host", "127.0.0.1",
                                   "--dashboard-address", ":0"], env=self.env, stdout=self.log, stderr=self.log, start_new_session=True, cwd="/")
        self.workers.append(worker)
        return worker

    def wait_for_workers(self, n, timeout=60):
        from distributed import Client
        with Client(self.address, timeout="30s") as client:
            client.wait_for_workers(n, timeout=timeout)

    def kill_worker(self, worker):
        """SIGKILL: the worker and the qgis_process it runs die at once, without a word to the scheduler."""
        os.killpg(worker.pid, signal.SIGKILL)
        worker.wait()
        self.workers.remove(worker)

    def stop(self):
        for p in self.workers + [self.scheduler]:
            try:
                os.killpg(p.pid, signal.SIGTERM)
            except ProcessLookupError:
                pass
        for p in self.workers + [self.scheduler]:
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
        self.log.close()


def installed_batch(home):
    """The geostation-batch that scripts/install-plugin.sh linked into the home's ~/.local/bin."""
    return os.path.join(home, ".local", "bin", "geostation-batch")


def batch(home, *args, wait=True, log=None):
    """Runs the installed geostation-batch as a user does; returns the finished process (or the running one)."""
    command = [installed_batch(home), *args, "--qgis-home", home]
    env = dict(os.environ, HOME=home)
    if not wait:
        return subprocess.Popen(command, env=env, stdout=log, stderr=log, start_new_session=True)
    return subprocess.run(command, env=env, capture_output=True, text=True, timeout=1800)


def read_lines(path, layer=None):
    """The lines of a layer as arrays of XY vertices, with their attributes."""
    ds = ogr.Open(path)
    lyr = ds.GetLayerByName(layer) if layer else ds.GetLayer(0)
    out = []
    for f in lyr:
        g = f.GetGeometryRef()
        if g is None:
            continue
        parts = [g.GetGeometryRef(i) for i in range(g.GetGeometryCount())] if g.GetGeometryCount() else [g]
        for part in parts:
            pts = np.array([part.GetPoint(i)[:2] for i in range(part.GetPointCount())])
            if len(pts) >= 2:
                out.append((pts, f.items()))
    return out


def samples(pts, step=1.0):
    """Points every `step` along a polyline, with unit directions."""
    seg = np.diff(pts, axis=0)
    lengths = np.hypot(seg[:, 0], seg[:, 1])
    out, dirs = [], []
    for (a, d, length) in zip(pts[:-1], seg, lengths):
        if length <= 0:
            continue
        n = max(1, int(np.ceil(length / step)))
        t = (np.arange(n) + 0.5) / n
        out.append(a + np.outer(t, d))
        dirs.append(np.repeat([d / length], n, axis=0))
    if not out:
        return np.zeros((0, 2)), np.zeros((0, 2)), 0.0
    return np.vstack(out), np.vstack(dirs), lengths.sum()


def distances(points, lines):
    """For each point: the distance to the nearest segment of `lines` and that segment's unit direction."""
    best = np.full(len(points), np.inf)
    best_dir = np.zeros((len(points), 2))
    for pts in lines:
        a, b = pts[:-1], pts[1:]
        d = b - a
        dd = np.maximum((d ** 2).sum(1), 1e-12)
        t = np.clip(((points[:, None, :] - a[None]) * d[None]).sum(2) / dd[None], 0, 1)
        q = a[None] + t[..., None] * d[None]
        dist = np.hypot(*(points[:, None, :] - q).transpose(2, 0, 1))
        k = dist.argmin(1)
        m = dist[np.arange(len(points)), k]
        better = m < best
        best[better] = m[better]
        best_dir[better] = (d[k] / np.sqrt(dd[k])[:, None])[better]
    return best, best_dir


def buffer_score(result, truth, buffer_m, inside=None):
    """Completeness and correctness (buffer method), truth and result cut to `inside` (a function of points -> bool mask)."""
    def cut(lines):
        pts = [samples(l)[0] for l in lines]
        pts = np.vstack(pts) if pts else np.zeros((0, 2))
        return pts[inside(pts)] if inside is not None and len(pts) else pts
    t, r = cut(truth), cut(result)
    completeness = float((distances(t, result)[0] <= buffer_m).mean()) if len(t) and result else 0.0
    correctness = float((distances(r, truth)[0] <= buffer_m).mean()) if len(r) and truth else 0.0
    return completeness, correctness, len(t), len(r)


def trimmed(pts, end_m):
    """The polyline without its first and last `end_m` (None when nothing is left)."""
    seg = np.hypot(*np.diff(pts, axis=0).T)
    along = np.concatenate([[0.0], np.cumsum(seg)])
    if along[-1] <= 2 * end_m:
        return None
    keep = (along > end_m) & (along < along[-1] - end_m)
    first = np.interp(end_m, along, pts[:, 0]), np.interp(end_m, along, pts[:, 1])
    last = np.interp(along[-1] - end_m, along, pts[:, 0]), np.interp(along[-1] - end_m, along, pts[:, 1])
    return np.vstack([first, pts[keep], last])


def doubled_share(lines, tolerance_m=2.0, parallel_deg=30.0, node_m=5.0):
    """The share of the lines' length lying within `tolerance_m` of another of them and about parallel: a road twice.

    Within `node_m` of a line's ends it is a node (a junction, a line continued), not a repeat: left out on both sides."""
    total = doubled = 0
    cos = np.cos(np.radians(parallel_deg))
    inner = [trimmed(l, node_m) for l in lines]
    for i, pts in enumerate(lines):
        p, d, _ = samples(pts)
        total += len(p)
        if inner[i] is None:
            continue
        p, d, _ = samples(inner[i])
        others = [l for j, l in enumerate(inner) if j != i and l is not None]
        if not others or not len(p):
            continue
        dist, direction = distances(p, others)
        doubled += int(((dist <= tolerance_m) & (np.abs((d * direction).sum(1)) >= cos)).sum())
    return doubled / total if total else 0.0


def polygon_mask(polygons):
    """A function of points -> whether each lies in one of the OGR polygons."""
    def inside(points):
        mask = np.zeros(len(points), dtype=bool)
        for poly in polygons:
            env = poly.GetEnvelope()
            near = (points[:, 0] >= env[0]) & (points[:, 0] <= env[1]) & (points[:, 1] >= env[2]) & (points[:, 1] <= env[3])
            for k in np.nonzero(near & ~mask)[0]:
                pt = ogr.Geometry(ogr.wkbPoint)
                pt.AddPoint_2D(float(points[k, 0]), float(points[k, 1]))
                mask[k] = poly.Contains(pt)
        return mask
    return inside
