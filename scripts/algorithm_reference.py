#!/usr/bin/python3
"""Writes docs/algorithms/: one page per GeoStation Processing algorithm, in the
layout of QGIS's own algorithm reference (what it does; its parameters with
label, name, type, default and what it takes; its outputs; a qgis_process
example), read from the installed provider itself, so the pages say what
the algorithms do. --check compares instead of writing (the test).

    scripts/algorithm_reference.py [--qgis-home DIR] [--check] [OUT_DIR]
"""

import argparse
import json
import os
import re
import subprocess
import sys

TYPE_NAMES = {
    "file": "file", "raster": "raster layer", "source": "vector features", "vector": "vector layer", "multilayer": "layers (one or more)",
    "string": "text", "number": "number", "enum": "choice", "boolean": "yes/no", "sink": "vector output", "fileDestination": "file output",
    "folderDestination": "folder output", "rasterDestination": "raster output", "vectorDestination": "vector output", "crs": "CRS",
    "field": "field", "extent": "extent", "point": "point", "band": "band", "distance": "distance", "matrix": "table", "expression": "expression",
}


def qgis(home, *args):
    env = dict(os.environ, HOME=home, QT_QPA_PLATFORM="offscreen", XDG_RUNTIME_DIR=home)
    done = subprocess.run(["qgis_process.bin", *args], env=env, capture_output=True, text=True, timeout=300)
    if done.returncode != 0:
        sys.exit("algorithm_reference.py: qgis_process %s failed: %s" % (" ".join(args), done.stderr.strip().splitlines()[-1:]))
    return done.stdout


def geostation_algorithms(home):
    listing = qgis(home, "list")
    return sorted(set(re.findall(r"\b(geostation:[a-z_]+)\b", listing)))


def description(text_help):
    """The Description section of `qgis_process help`."""
    match = re.search(r"-+\nDescription\n-+\n(.*?)\n-+\nArguments", text_help, re.S)
    return match.group(1).strip() if match else ""


def takes(p):
    """What a parameter takes, from its definition: options, range, optional or not."""
    raw = p.get("raw_definition", {})
    parts = []
    if raw.get("options"):
        parts.append("one of: " + ", ".join("`%s`" % o for o in raw["options"]))
    low, high = raw.get("min"), raw.get("max")
    if low is not None and high is not None and p["type"]["id"] == "number" and not (low < -1e300 or high > 1e300):
        parts.append("%g to %g" % (low, high))
    if p.get("optional"):
        parts.append("optional")
    if p.get("is_advanced"):
        parts.append("advanced")
    return "; ".join(parts)


def default(p):
    value = p.get("default_value")
    if value is None or value == "":
        return ""
    if isinstance(value, float) and value.is_integer():
        value = int(value)
    return "`%s`" % value


def page(algorithm, details, text_help):
    alg_id = algorithm.split(":", 1)[1]
    params = details["parameters"]
    inputs = [(n, p) for n, p in params.items() if not p["is_destination"]]
    destinations = [(n, p) for n, p in params.items() if p["is_destination"]]
    lines = ["# %s (`%s`)" % (details["algorithm_details"]["name"], algorithm), "",
             "Group: %s. Tags: %s." % (details["algorithm_details"]["group"], ", ".join(details["algorithm_details"]["tags"])), "",
             description(text_help).replace("<", "&lt;").replace(">", "&gt;"), "",
             "## Parameters", "", "| Label | Name | Type | Default | Takes |", "|---|---|---|---|---|"]
    for name, p in inputs:
        lines.append("| %s | `%s` | %s | %s | %s |" % (p["description"], name, TYPE_NAMES.get(p["type"]["id"], p["type"]["id"]), default(p), takes(p)))
    lines += ["", "## Outputs", "", "| Label | Name | Type | Written |", "|---|---|---|---|"]
    for name, p in destinations:
        written = "always" if not p["optional"] else ("unless left out" if p.get("raw_definition", {}).get("create_by_default", True) else "only when asked for")
        lines.append("| %s | `%s` | %s | %s |" % (p["description"], name, TYPE_NAMES.get(p["type"]["id"], p["type"]["id"]), written))
    others = [(n, o) for n, o in details.get("outputs", {}).items() if n not in params]
    for name, o in others:
        lines.append("| %s | `%s` | %s | always |" % (o["description"], name, o["type"].replace("output", "").lower() or "value"))
    required = [n for n, p in inputs if not p["optional"] and p.get("default_value") is None]
    example = ["qgis_process.bin run %s --" % algorithm] + ["  %s=..." % n for n in required]
    main = next((n for n, p in destinations if not p["optional"]), destinations[0][0] if destinations else None)
    if main:
        example.append("  %s=%s" % (main, "out.gpkg" if params[main]["type"]["id"] in ("sink", "vectorDestination") else "out"))
    lines += ["", "## Example", "", "```sh", " \\\n".join(example), "```", "",
              "More on how it works, and the figures: [the Processing algorithms](../processing.md), [validation](../validation.md).", ""]
    return alg_id, "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir", nargs="?", default=os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "docs", "algorithms"))
    parser.add_argument("--qgis-home", default=os.environ.get("HOME", ""), help="the HOME whose QGIS profile has GeoStation installed")
    parser.add_argument("--check", action="store_true", help="compare with the pages instead of writing them")
    args = parser.parse_args()
    home = args.qgis_home
    pages = {}
    algorithms = geostation_algorithms(home)
    if not algorithms:
        sys.exit("algorithm_reference.py: qgis_process lists no geostation algorithm: install the plugin into the profile of " + home)
    for algorithm in algorithms:
        raw = qgis(home, "help", algorithm, "--json")
        details = json.loads(raw[raw.find("{"):])
        alg_id, text = page(algorithm, details, qgis(home, "help", algorithm))
        pages[alg_id + ".md"] = text
    index = ["# The Processing algorithms, one page each", "",
             "Generated from the installed provider by `scripts/algorithm_reference.py`; "
             "the methods are described in [processing.md](../processing.md).", ""]
    for algorithm in algorithms:
        alg_id = algorithm.split(":", 1)[1]
        index.append("- [`%s`](%s.md) - %s" % (alg_id, alg_id, pages[alg_id + ".md"].splitlines()[0][2:].split(" (`")[0]))
    pages["README.md"] = "\n".join(index) + "\n"
    if args.check:
        stale = []
        for name, text in pages.items():
            path = os.path.join(args.out_dir, name)
            if not os.path.exists(path) or open(path).read() != text:
                stale.append(name)
        extra = sorted(set(os.listdir(args.out_dir)) - set(pages)) if os.path.isdir(args.out_dir) else []
        if stale or extra:
            sys.exit("docs/algorithms is out of date (%s): run scripts/algorithm_reference.py" % ", ".join(stale + extra))
        print("docs/algorithms matches the %d installed algorithms" % len(algorithms))
        return 0
    os.makedirs(args.out_dir, exist_ok=True)
    for name, text in pages.items():
        with open(os.path.join(args.out_dir, name), "w") as f:
            f.write(text)
    print("wrote %d pages into %s" % (len(pages), args.out_dir))
    return 0


if __name__ == "__main__":
    sys.exit(main())
