"""One unit of work, run on a Dask worker: one qgis_process run whose outputs
are staged in the work dir and made the unit's in one rename, then recorded by
a manifest entry. A unit whose entry is there is done: running it again does
nothing, so a unit a lost worker had begun is simply run elsewhere, and a run
killed halfway resumes where it stopped.

Layout of the work dir:
    units/<unit id>/          the unit's outputs (complete or absent)
    manifest/<unit id>.json   the entry that says it is complete (digest, time, worker)
    staging/                  runs in progress; anything left here is from a run that died
"""

import hashlib
import json
import os
import resource
import shutil
import socket
import tempfile
import time

from . import qgis


class UnitFailed(Exception):
    """A unit's qgis_process run failed: its one sentence."""


def digest(algorithm, parameters):
    """What makes two runs of a unit the same: the algorithm and its parameters (outputs excluded)."""
    text = json.dumps({"algorithm": algorithm, "parameters": parameters}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def unit_dir(work_dir, unit_id):
    return os.path.join(work_dir, "units", unit_id)


def manifest_path(work_dir, unit_id):
    return os.path.join(work_dir, "manifest", unit_id + ".json")


def completed(work_dir, spec):
    """The manifest entry of a unit done with the same digest, or None."""
    try:
        with open(manifest_path(work_dir, spec["id"])) as f:
            entry = json.load(f)
    except (OSError, ValueError):
        return None
    if entry.get("digest") != spec["digest"] or not os.path.isdir(unit_dir(work_dir, spec["id"])):
        return None
    return entry


def write_atomically(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fd, staged = tempfile.mkstemp(dir=os.path.dirname(path), prefix=".staged-")
    with os.fdopen(fd, "w") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(staged, path)


def run_unit(spec, work_dir, executable, qgis_home, timeout=None):
    """Runs a unit (see the module comment) and returns its manifest entry.

    `spec`: id, algorithm, digest, parameters (inputs), outputs (parameter -> file name in the unit's folder).
    Raises UnitFailed with the algorithm's sentence when qgis_process fails."""
    done = completed(work_dir, spec)
    if done:
        return dict(done, skipped=True)
    staging_root = os.path.join(work_dir, "staging")
    os.makedirs(staging_root, exist_ok=True)
    staging = tempfile.mkdtemp(dir=staging_root, prefix=spec["id"] + ".")
    try:
        outputs = os.path.join(staging, "outputs")
        os.makedirs(outputs)
        home = qgis.private_home(qgis_home, os.path.join(staging, "home"))
        parameters = dict(spec["parameters"])
        for name, file_name in spec["outputs"].items():
            parameters[name] = os.path.join(outputs, file_name)
            os.makedirs(os.path.dirname(parameters[name]), exist_ok=True)
        start = time.time()
        try:
            code, out, err = qgis.run(executable, home, spec["algorithm"], parameters, timeout=timeout)
        except FileNotFoundError:
            raise UnitFailed("%s was not found on %s" % (executable, socket.gethostname()))
        except Exception as e:  # a timeout
            raise UnitFailed("%s: %s" % (type(e).__name__, e))
        seconds = time.time() - start
        if code != 0:
            raise UnitFailed(qgis.failure_sentence(code, out, err))
        missing = [f for f in spec["outputs"].values() if not os.path.exists(os.path.join(outputs, f))]
        if missing:
            raise UnitFailed("qgis_process succeeded but wrote no %s" % ", ".join(missing))
        # the outputs become the unit's in one rename; then the entry says so
        final = unit_dir(work_dir, spec["id"])
        os.makedirs(os.path.dirname(final), exist_ok=True)
        if os.path.exists(final):
            shutil.rmtree(final)  # from a run that died between the rename and its entry
        os.rename(outputs, final)
        # the largest qgis_process this worker has run so far (Linux: kB)
        peak_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0
        entry = {"id": spec["id"], "digest": spec["digest"], "algorithm": spec["algorithm"], "seconds": seconds, "peak_rss_mb": round(peak_mb, 1),
                 "worker": socket.gethostname() + ":" + str(os.getpid()), "finished": time.time()}
        write_atomically(manifest_path(work_dir, spec["id"]), json.dumps(entry, indent=1))
        return dict(entry, skipped=False)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def check_access(paths, work_dir, executable, qgis_home):
    """Run on every worker before the units: what it cannot read, write or run (an empty list: all well)."""
    problems = []
    for path in paths:
        if not os.access(path, os.R_OK):
            problems.append("cannot read %s" % path)
    if not os.access(work_dir, os.W_OK):
        problems.append("cannot write %s" % work_dir)
    if shutil.which(executable) is None and not os.access(executable, os.X_OK):
        problems.append("has no %s" % executable)
    if not qgis.has_geostation(qgis_home):
        problems.append("has no GeoStation plugin in the QGIS profile of %s" % qgis_home)
    return problems
