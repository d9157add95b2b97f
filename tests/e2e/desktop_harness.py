"""Running QGIS desktop for the end-to-end tests: GeoStation installed into a
temporary profile, qgis.bin under xvfb-run with a --code script."""

import os
import subprocess


def install_plugin(source_dir, build_dir, tmp):
    """Installs the plugin into a profile below `tmp`; returns (env, profiles).
    QGIS gets a HOME and a temporary folder of its own (it counts layers under
    its temporary folder as temporary and asks about them when quitting)."""
    home = os.path.join(tmp, "home")
    profiles = os.path.join(tmp, "profiles")
    os.makedirs(os.path.join(home, "tmp"))
    env = dict(os.environ, HOME=home, XDG_RUNTIME_DIR=home, TMPDIR=os.path.join(home, "tmp"))
    subprocess.run([os.path.join(source_dir, "scripts", "install-plugin.sh"), "--build-dir", build_dir,
                    "--profile-dir", os.path.join(profiles, "profiles", "default")],
                   env=env, check=True, capture_output=True)
    return env, profiles


def run_qgis(script, env, profiles, screen="1400x900", timeout=300):
    """Runs QGIS with the script; returns (exit code, the end of its output).
    A QGIS that does not quit within `timeout` seconds is stopped (exit -1)."""
    env = dict(env, GEOSTATION_E2E_SCRIPTS=os.path.dirname(os.path.abspath(script)))
    try:
        run = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 %sx24" % screen, "qgis.bin",
                              "--profiles-path", profiles, "--nologo", "--code", script],
                             env=env, capture_output=True, text=True, timeout=timeout)
        return run.returncode, run.stdout[-4000:] + run.stderr[-4000:]
    except subprocess.TimeoutExpired as e:
        subprocess.run(["pkill", "-f", os.path.basename(script)])
        return -1, "QGIS did not finish in %d s\n" % timeout + str(e.stdout or "")[-2000:] + str(e.stderr or "")[-2000:]


def distance_to_polyline(p, line):
    """Plan distance from a point to a polyline, and its height above the line there."""
    best = (float("inf"), 0.0)
    for a, b in zip(line, line[1:]):
        dx, dy = b[0] - a[0], b[1] - a[1]
        t = max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy or 1.0)))
        d = ((a[0] + t * dx - p[0]) ** 2 + (a[1] + t * dy - p[1]) ** 2) ** 0.5
        if d < best[0]:
            best = (d, p[2] - (a[2] + t * (b[2] - a[2])))
    return best
