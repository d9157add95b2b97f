"""How a headless qgis_process is run: its executable, a private HOME per run
with the user's GeoStation profile linked into it, and the one sentence of a
failed run."""

import json
import os
import shutil
import subprocess

PROFILE = os.path.join(".local", "share", "QGIS", "QGIS3", "profiles", "default")

# stderr lines that are QGIS's or Python's noise, never the algorithm's message
NOISE = ("QStandardPaths:", "DeprecationWarning", "<string>:", "Warning: ", "qt.qpa", "Application path not initialized",
         "ERROR 1: Unable to compute a transformation")


def profile_of(qgis_home):
    return os.path.join(qgis_home, PROFILE)


def has_geostation(qgis_home):
    """Whether the GeoStation provider is installed in the profile under `qgis_home`."""
    profile = profile_of(qgis_home)
    return os.path.isdir(os.path.join(profile, "geostation")) and os.path.isdir(os.path.join(profile, "python", "plugins", "geostation_processing"))


def private_home(qgis_home, home):
    """A HOME of its own for one qgis_process run: the profile's GeoStation folders linked, its settings copied.

    Runs side by side never write into one profile (QGIS rewrites its settings on exit)."""
    source, target = profile_of(qgis_home), profile_of(home)
    os.makedirs(os.path.join(target, "python", "plugins"), exist_ok=True)
    os.makedirs(os.path.join(target, "QGIS"), exist_ok=True)
    for part in ("geostation", os.path.join("python", "plugins", "geostation_processing")):
        link = os.path.join(target, part)
        if not os.path.lexists(link):
            os.symlink(os.path.join(source, part), link)
    settings = os.path.join(source, "QGIS", "QGIS3.ini")
    if os.path.exists(settings):
        shutil.copyfile(settings, os.path.join(target, "QGIS", "QGIS3.ini"))
    return home


def environment(home):
    env = dict(os.environ, HOME=home, QT_QPA_PLATFORM="offscreen", XDG_RUNTIME_DIR=home)
    env.pop("GEOSTATION_PROVIDER_LIBRARY", None)
    return env


def argument(name, value):
    """NAME=value as qgis_process takes it (a list: the parameter repeated, as for INPUTS)."""
    if isinstance(value, (list, tuple)):
        return ["%s=%s" % (name, v) for v in value]
    if isinstance(value, bool):
        value = "true" if value else "false"
    return ["%s=%s" % (name, value)]


def run(executable, home, algorithm, parameters, timeout=None):
    """Runs one algorithm; returns (return code, stdout, stderr)."""
    args = [executable, "run", algorithm, "--"]
    for name, value in parameters.items():
        args += argument(name, value)
    done = subprocess.run(args, env=environment(home), capture_output=True, text=True, timeout=timeout)
    return done.returncode, done.stdout, done.stderr


def failure_sentence(returncode, stdout, stderr):
    """The algorithm's own sentence of a failed run (its last message line on stderr), else what is known."""
    for text in (stderr, stdout):  # stdout holds the inputs echoed; the message is on stderr
        lines = [l.strip() for l in text.splitlines() if l.strip()]
        lines = [l for l in lines if not l.startswith(NOISE) and not l.startswith("----") and l not in ("Results", "Inputs")]
        if lines:
            last = lines[-1]
            return last.split("\t", 1)[1].strip() if last.startswith(("ERROR:", "Error:")) and "\t" in last else last
    if returncode < 0:
        return "qgis_process was killed by signal %d" % -returncode
    return "qgis_process stopped with status %d and no message" % returncode


def algorithm_help(executable, qgis_home, algorithm, scratch):
    """The algorithm's parameters and outputs as `qgis_process help --json` gives them; raises RuntimeError with one sentence."""
    home = private_home(qgis_home, os.path.join(scratch, "help-home"))
    try:
        done = subprocess.run([executable, "help", algorithm, "--json"], env=environment(home), capture_output=True, text=True, timeout=300)
    except FileNotFoundError:
        raise RuntimeError("%s was not found: install QGIS (Debian package qgis) or give --qgis-process" % executable)
    if done.returncode != 0:
        raise RuntimeError("qgis_process does not know %s: install the GeoStation plugin (scripts/install-plugin.sh) "
                           "into the profile of %s, or give --qgis-home" % (algorithm, qgis_home))
    start = done.stdout.find("{")
    return json.loads(done.stdout[start:])
