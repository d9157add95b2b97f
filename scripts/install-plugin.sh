#!/usr/bin/env bash
# Installs the built GeoStation plugin, Processing provider and Python bridge
# into a QGIS profile and enables them. Idempotent; --uninstall removes it all.
#
#   scripts/install-plugin.sh [--build-dir DIR] [--profile-dir DIR] [--uninstall]
#
# The profile defaults to $HOME/.local/share/QGIS/QGIS3/profiles/default.
# Afterwards `qgis_process.bin list` shows the geostation provider and QGIS
# desktop loads the plugin at start; geostation-batch is linked into
# ~/.local/bin.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source_dir="$(dirname "$here")"
build_dir="$source_dir/build"
profile_dir="${HOME}/.local/share/QGIS/QGIS3/profiles/default"
own_profile=0
uninstall=0

while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build_dir="$2"; shift 2 ;;
    --profile-dir) profile_dir="$2"; own_profile=1; shift 2 ;;
    --uninstall) uninstall=1; shift ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "install-plugin.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

target="$profile_dir/geostation"
bridge="$profile_dir/python/plugins/geostation_processing"
settings="$profile_dir/QGIS/QGIS3.ini"

# Edits the profile's QGIS3.ini through QSettings, which keeps every other
# setting as QGIS wrote it.
edit_settings() {
  mkdir -p "$(dirname "$settings")"
  /usr/bin/python3 - "$settings" "$1" "$target/plugins" <<'PY'
import sys
from PyQt5.QtCore import QSettings
path, action, plugin_dir = sys.argv[1:4]
s = QSettings(path, QSettings.IniFormat)
paths = s.value("plugins/searchPathsForPlugins", [])
if isinstance(paths, str):
    paths = [paths] if paths else []
paths = [p for p in paths if p != plugin_dir]
if action == "install":
    paths.append(plugin_dir)
    s.setValue("Plugins/libgeostationplugin", True)
    s.setValue("PythonPlugins/geostation_processing", True)
else:
    s.remove("Plugins/libgeostationplugin")
    s.remove("PythonPlugins/geostation_processing")
if len(paths) == 1:
    s.setValue("plugins/searchPathsForPlugins", paths[0])  # plain text; QGIS reads it with toStringList()
elif paths:
    s.setValue("plugins/searchPathsForPlugins", paths)
else:
    s.remove("plugins/searchPathsForPlugins")
s.sync()
sys.exit(0 if s.status() == QSettings.NoError else 1)
PY
}

batch_link="${HOME}/.local/bin/geostation-batch"

if [ "$uninstall" = 1 ]; then
  rm -rf "$target" "$bridge"
  [ -L "$batch_link" ] && [ "$(readlink "$batch_link")" = "$target/bin/geostation-batch" ] && rm -f "$batch_link"
  [ -f "$settings" ] && edit_settings uninstall
  echo "GeoStation removed from $profile_dir"
  exit 0
fi

for built in core/libgeostation_base.so core/libgeostation_photogrammetry.so core/libgeostation_workstation.so core/libgeostation_simulation.so \
  processing/libgeostation_processing.so plugin/libgeostationplugin.so; do
  if [ ! -e "$build_dir/$built" ]; then
    echo "install-plugin.sh: $build_dir/$built is missing; build first (scripts/test.sh or cmake --build build)" >&2
    exit 1
  fi
done

# Install into a fresh staging folder, then swap it in, so a failed install
# leaves the previous one working.
staging="$profile_dir/.geostation-staging"
rm -rf "$staging"
cmake --install "$build_dir" --prefix "$staging" > /dev/null
# the old installation is renamed aside first and removed only once the new one is in place: QGIS never
# sees a half-copied plugin, and an interrupted swap leaves the old one beside it (*.old)
old="$profile_dir/.geostation-old.$$"
mkdir -p "$old" "$(dirname "$bridge")"
[ -e "$target" ] && mv "$target" "$old/plugin"
[ -e "$bridge" ] && mv "$bridge" "$old/bridge"
mv "$staging/python/geostation_processing" "$bridge"
rmdir "$staging/python"
mv "$staging" "$target"
rm -rf "$old"
edit_settings install
# the batch command on the PATH of a login shell (~/.local/bin), unless another one is there;
# not for a profile of its own (--profile-dir), whose batch stays in its bin/
if [ "$own_profile" = 0 ] && { [ ! -e "$batch_link" ] || [ -L "$batch_link" ]; }; then
  mkdir -p "$(dirname "$batch_link")"
  ln -sfn "$target/bin/geostation-batch" "$batch_link"
fi

echo "GeoStation installed into $profile_dir"
echo "  plugin:   $target/plugins/libgeostationplugin.so"
echo "  provider: $target/lib/libgeostation_processing.so"
echo "  bridge:   $bridge"
echo "  batch:    $target/bin/geostation-batch$([ "$own_profile" = 0 ] && echo ", linked as $batch_link")"
