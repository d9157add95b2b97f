"""What the end-to-end tests of qgis_process.bin share: the environment a
headless QGIS runs in (its own HOME, no display) and a temporary profile with
the plugin installed into it."""

import os
import subprocess
import tempfile


def qgis_env(home):
    """The environment of a headless QGIS whose profile lives in `home` (the provider found through the profile only)."""
    env = dict(os.environ, HOME=home, QT_QPA_PLATFORM="offscreen", XDG_RUNTIME_DIR=home)
    env.pop("GEOSTATION_PROVIDER_LIBRARY", None)
    return env


def install_plugin(source_dir, build_dir, home, *extra):
    subprocess.run([os.path.join(source_dir, "scripts", "install-plugin.sh"), "--build-dir", build_dir, *extra],
                   env=qgis_env(home), check=True, capture_output=True, text=True)


def temporary_profile(source_dir, build_dir, prefix):
    """A new temporary folder and, in it, a home with the plugin installed: (folder, home)."""
    tmp = tempfile.mkdtemp(prefix=prefix)
    home = os.path.join(tmp, "home")
    os.makedirs(home)
    install_plugin(source_dir, build_dir, home)
    return tmp, home
