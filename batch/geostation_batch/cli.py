"""geostation-batch COMMAND [options]: the command line (see docs/batch.md).

Exit status: 0 every unit done and merged, 3 the run is partial (units named
in the report failed; the others are merged), 1 bad input (one sentence)."""

import argparse
import csv
import io
import os
import shutil
import sys
import tempfile
import time

from . import cluster, merge, plan, qgis, report, unit

COMMANDS = {
    "extract": ("geostation:extract_roads", "extract the road network of every stereo pair of a block and merge them into one"),
    "monoplot": ("geostation:monoplot", "monoplot the features digitised on an image, in chunks of features"),
    "project": ("geostation:project_to_image", "project map features into an image, in chunks of features"),
    "trace": ("geostation:trace_road_lines", "trace road lines through a run from seeds, one unit per seed, joined per line_id"),
    "revise": ("geostation:revise_roads", "revise a road map against every stereo pair of a block and merge the revisions into one"),
}
# parameters the batch sets for each unit itself
PER_UNIT = {"extract": {"LEFT", "RIGHT"}, "monoplot": set(), "project": set(), "trace": {"SEEDS", "MAX_STATIONS"}, "revise": {"LEFT", "RIGHT"}}
PAIRED = ("extract", "revise")  # one unit per stereo pair
CHUNKED_INPUT = {"monoplot": "INPUT", "project": "INPUT"}
PATH_TYPES = {"file", "raster", "source", "vector", "layer", "multilayer", "mesh", "pointcloud"}

EXIT_OK, EXIT_BAD_INPUT, EXIT_PARTIAL = 0, 1, 3


class Parser(argparse.ArgumentParser):
    def error(self, message):  # bad input is status 1, in one sentence
        sys.stderr.write("geostation-batch: %s (see %s --help)\n" % (message, self.prog))
        sys.exit(EXIT_BAD_INPUT)


def say(text):
    sys.stderr.write(text + "\n")
    sys.stderr.flush()


def common_options(parser):
    parser.add_argument("--scheduler", metavar="ADDRESS", help="a running dask-scheduler (tcp://host:8786); none: a local cluster")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1, help="local cluster: worker processes (default: the cores, %(default)s)")
    parser.add_argument("--work-dir", metavar="DIR", help="units' outputs and manifest, kept for a resumed run (default: OUTPUT.work)")
    parser.add_argument("--retries", type=int, default=2, help="times a failed unit is run again (default %(default)s)")
    parser.add_argument("--unit-size", type=int, default=2000, help="monoplot, project: features per unit (default %(default)s)")
    parser.add_argument("--unit-timeout", type=float, help="seconds a unit may take before it counts as failed")
    parser.add_argument("--output", required=True, metavar="PATH", help="the merged output")
    parser.add_argument("--report", metavar="PATH", help="the run report (JSON; a readable .txt beside it; default in the work dir)")
    parser.add_argument("--qgis-process", default="qgis_process.bin", metavar="PATH", help="the qgis_process executable (default %(default)s)")
    parser.add_argument("--qgis-home", default=os.environ.get("HOME", ""), metavar="DIR",
                        help="the HOME whose QGIS profile has GeoStation installed (default: $HOME)")


def algorithm_options(parser, command, help_json):
    """The algorithm's own inputs, as options named in lower case (LEFT: --left)."""
    names = {}
    for name, p in sorted(help_json["parameters"].items()):
        if p["is_destination"] or name in PER_UNIT[command]:
            continue
        option = name.lower()
        flags = ["--" + option] + (["--" + option.replace("_", "-")] if "_" in option else [])
        kind = p["type"]["id"]
        required = not p["optional"] and p["default_value"] is None and kind != "enum"
        parser.add_argument(*flags, dest="alg_" + name, required=required, metavar=kind.upper(),
                            help="%s%s" % (p["description"], "" if p["default_value"] is None else " (default %s)" % p["default_value"]))
        names[name] = kind
    if command in PAIRED:
        parser.add_argument("--pairs", metavar="TABLE", help="the stereo pairs (a table with fields left, right); default: neighbours along each strip")
        parser.add_argument("--left", help="one pair only: its left image")
        parser.add_argument("--right", help="one pair only: its right image")
    if command == "revise":
        parser.add_argument("--new", metavar="PATH", help="the roads the pairs show that no map road explains, merged (the pairs are extracted only when asked)")
        parser.add_argument("--vertices", metavar="PATH", help="the merged courses' measured vertices with their sigma (a table)")
    if command == "trace":
        parser.add_argument("--seeds", required=True, metavar="TABLE",
                            help="seed_id, image_id, col, row [, direction_deg] [, line_id: seeds of one line, traced in pieces]")
        parser.add_argument("--max-stations", "--max_stations", type=int, default=0, help="stations the last seed of a line traces (0: to the end of the run)")
        parser.add_argument("--overlap-stations", type=int, default=100, help="stations a piece traces past the next seed's station (default %(default)s)")
    return names


def absolute(value):
    path, sep, rest = value.partition("|")
    return os.path.abspath(path) + sep + rest if os.path.exists(path) else value


def fingerprint(value):
    """A file's size and time, so a changed input is not taken for a done unit's."""
    path = value.partition("|")[0]
    try:
        st = os.stat(path)
    except OSError:
        return value
    return "%s@%d:%d" % (value, st.st_size, st.st_mtime_ns)


def check_arguments(args, inputs, kinds):
    """Bad input found before any unit runs: one sentence (plan.BadInput)."""
    if args.workers < 1 or args.retries < 0:
        raise plan.BadInput("--workers must be at least 1 and --retries not negative")
    if args.unit_timeout is not None and not args.unit_timeout > 0:
        raise plan.BadInput("--unit-timeout must be positive (seconds)")
    for name, value in inputs.items():
        if kinds[name] in PATH_TYPES and not os.path.exists(value.partition("|")[0]):
            raise plan.BadInput("--%s %s does not exist" % (name.lower(), value.partition("|")[0]))


def plan_units(command, args, algorithm, inputs, work_dir):
    """The units: (spec list, description of what a unit is)."""
    specs = []

    def add(unit_id, parameters, outputs, basis):
        specs.append({"id": unit_id, "algorithm": algorithm, "parameters": parameters, "outputs": outputs,
                      "digest": unit.digest(algorithm, basis)})

    basis = {name: fingerprint(v) for name, v in inputs.items()}
    if command in PAIRED:
        block = plan.read_block(inputs["BLOCK"])
        if args.left or args.right:
            if not (args.left and args.right):
                raise plan.BadInput("--left and --right go together (one pair), or give neither")
            pairs = [(args.left, args.right)]
        elif args.pairs:
            pairs = plan.table_pairs(args.pairs, block)
        else:
            pairs = plan.strip_pairs(block)
        if not pairs:
            raise plan.BadInput("the block %s has no two oriented images of one camera side by side along a strip: give --pairs" % inputs["BLOCK"])
        for left, right in pairs:
            name = plan.pair_name(left, right)
            outputs = {"OUTPUT": name + ".gpkg", "REPORT": "report.json"}
            if command == "revise":
                # each output a file of the pair's name, so that the merges name the pairs
                outputs.update(VERTICES=os.path.join("vertices", name + ".gpkg"), **({"NEW": os.path.join("new", name + ".gpkg")} if args.new else {}))
            add("pair-" + name, dict(inputs, LEFT=left, RIGHT=right), outputs,
                dict(basis, LEFT=left, RIGHT=right, **({"outputs": sorted(outputs)} if command == "revise" else {})))
        return specs, "%d stereo pairs" % len(pairs)
    if command == "trace":
        block = plan.read_block(inputs["BLOCK"])
        seeds_path = absolute(args.seeds)
        if args.overlap_stations < 1 or args.max_stations < 0:
            raise plan.BadInput("--overlap-stations must be at least 1 and --max-stations not negative")
        pieces = plan.seed_pieces(plan.read_table(seeds_path, "seeds"), block, args.max_stations, args.overlap_stations)
        folder = os.path.join(work_dir, "inputs", "seeds")
        os.makedirs(folder, exist_ok=True)
        for line_id, order, row, stations in pieces:
            seed_file = os.path.join(folder, "%s.csv" % row["seed_id"])
            text = io.StringIO()
            writer = csv.DictWriter(text, fieldnames=list(row))
            writer.writeheader()
            writer.writerow(row)
            unit.write_atomically(seed_file, text.getvalue())
            add("seed-" + row["seed_id"], dict(inputs, SEEDS=seed_file, MAX_STATIONS=stations), {"OUTPUT": "piece.gpkg"},
                dict(basis, seed=row, stations=stations, line_id=line_id, order=order))
            specs[-1]["piece"] = (line_id, order, row["seed_id"])
        lines = len({p[0] for p in pieces})
        return specs, "%d seeds of %d lines" % (len(pieces), lines)
    # chunks of features, written once per input version
    source = inputs[CHUNKED_INPUT[command]]
    if args.unit_size < 1:
        raise plan.BadInput("--unit-size must be at least 1")
    folder = os.path.join(work_dir, "inputs", unit.digest("chunks", {"input": fingerprint(source), "size": args.unit_size}))
    marker = os.path.join(folder, "complete")
    if os.path.exists(marker):
        chunks = sorted(os.path.join(folder, f) for f in os.listdir(folder) if f.endswith(".gpkg"))
    else:
        shutil.rmtree(folder, ignore_errors=True)
        chunks = plan.write_chunks(source, args.unit_size, folder)
        unit.write_atomically(marker, "%d\n" % len(chunks))
    for i, chunk in enumerate(chunks):
        add("chunk-%05d" % i, dict(inputs, **{CHUNKED_INPUT[command]: chunk}), {"OUTPUT": "output.gpkg"},
            dict(basis, chunk=i, size=args.unit_size))
    return specs, "%d chunks of up to %d features" % (len(chunks), args.unit_size)


def merge_units(command, specs, entries, work_dir, args, say):
    done = [s for s in specs if s["id"] in entries]
    if not done:
        raise merge.MergeFailed("no unit is complete: nothing to merge")
    if command in PAIRED:
        def of(s, name):
            return os.path.join(unit.unit_dir(work_dir, s["id"]), s["outputs"][name])
        if command == "extract":
            return merge.road_networks([of(s, "OUTPUT") for s in done], args.output, args.qgis_process, args.qgis_home,
                                       os.path.join(work_dir, "merge-report.json"))
        merged = {"revision": merge.revisions([of(s, "OUTPUT") for s in done], [of(s, "VERTICES") for s in done], args.output, args.vertices,
                                              args.qgis_process, args.qgis_home, os.path.join(work_dir, "merge-report.json"))}
        if args.new:
            merged["new"] = merge.road_networks([of(s, "NEW") for s in done], args.new, args.qgis_process, args.qgis_home,
                                                os.path.join(work_dir, "new-merge-report.json"))
        return merged
    if command == "trace":
        pieces = [s["piece"] + (os.path.join(unit.unit_dir(work_dir, s["id"]), "piece.gpkg"),) for s in done]
        return merge.traced_pieces(pieces, args.output, args.qgis_process, args.qgis_home, work_dir, os.path.join(work_dir, "join-report.json"))
    outputs = [os.path.join(unit.unit_dir(work_dir, s["id"]), "output.gpkg") for s in done]
    return {"features": merge.feature_chunks(outputs, args.output)}


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    top = Parser(prog="geostation-batch", description="GeoStation's Processing algorithms over whole blocks, on Dask distributed.",
                 epilog="Commands: " + "; ".join("%s: %s" % (c, d) for c, (a, d) in COMMANDS.items()) +
                 ". 'geostation-batch COMMAND --help' lists a command's options (the algorithm's inputs in lower case).")
    top.add_argument("command", choices=sorted(COMMANDS))
    if not argv or argv[0] in ("-h", "--help"):
        top.print_help()
        return EXIT_OK if argv else EXIT_BAD_INPUT
    command = top.parse_args(argv[:1]).command
    algorithm, description = COMMANDS[command]

    # the algorithm's parameters, from the installed provider
    pre = argparse.ArgumentParser(add_help=False)
    pre.add_argument("--qgis-process", default="qgis_process.bin")
    pre.add_argument("--qgis-home", default=os.environ.get("HOME", ""))
    known, _ = pre.parse_known_args(argv[1:])
    scratch = tempfile.mkdtemp(prefix="geostation-batch-")
    try:
        started = time.time()
        help_json = qgis.algorithm_help(known.qgis_process, known.qgis_home, algorithm, scratch)
        start_up = time.time() - started
    except RuntimeError as e:
        say("geostation-batch: %s." % e)
        return EXIT_BAD_INPUT
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    parser = Parser(prog="geostation-batch " + command, description=description + " (%s)." % algorithm)
    common_options(parser)
    kinds = algorithm_options(parser, command, help_json)
    args = parser.parse_args(argv[1:])
    inputs = {}
    for name, kind in kinds.items():
        value = getattr(args, "alg_" + name)
        if value is not None:
            inputs[name] = absolute(value) if kind in PATH_TYPES else value
    args.output = os.path.abspath(args.output)
    for extra in ("new", "vertices"):
        if getattr(args, extra, None):
            setattr(args, extra, os.path.abspath(getattr(args, extra)))
    work_dir = os.path.abspath(args.work_dir or args.output + ".work")
    os.makedirs(work_dir, exist_ok=True)
    report_path = os.path.abspath(args.report or os.path.join(work_dir, "run-report.json"))

    run = report.Run(command, algorithm, work_dir, start_up)
    try:
        check_arguments(args, inputs, kinds)
        specs, what = plan_units(command, args, algorithm, inputs, work_dir)
    except plan.BadInput as e:
        say("geostation-batch: %s." % e)
        return EXIT_BAD_INPUT
    say("%s: %s, work dir %s" % (command, what, work_dir))
    # the manifest read once: what an earlier run completed is not run again
    entries, errors, pending = {}, {}, []
    for spec in specs:
        done = unit.completed(work_dir, spec)
        if done:
            entries[spec["id"]] = dict(done, skipped=True)
        else:
            pending.append(spec)
    if not pending:
        say("every unit is complete from an earlier run: merging only")
    else:
        if entries:
            say("%d of %d units are complete from an earlier run and are not run again" % (len(entries), len(specs)))
        try:
            client, local = cluster.connect(args.scheduler, args.workers, say)
        except ConnectionError as e:
            say("geostation-batch: %s." % e)
            return EXIT_BAD_INPUT
        try:
            paths = [v.partition("|")[0] for n, v in inputs.items() if kinds[n] in PATH_TYPES and os.path.exists(v.partition("|")[0])]
            kept = cluster.check_workers(client, paths, work_dir, args.qgis_process, args.qgis_home, say)
            if not kept:
                say("geostation-batch: no worker can run the units.")
                return EXIT_BAD_INPUT
            run.workers = len(kept)
            ran, errors = cluster.run_units(client, pending, len(entries), len(specs), work_dir, args.qgis_process, args.qgis_home, args.retries,
                                            args.unit_timeout)
            entries.update(ran)
        finally:
            client.close()
            if local is not None:
                local.close()
    run.units(specs, entries, errors)
    try:
        run.merge = merge_units(command, specs, entries, work_dir, args, say)
    except merge.MergeFailed as e:
        run.merge_error = str(e)
    status = EXIT_OK if not errors and run.merge_error is None else EXIT_PARTIAL
    run.finish(status, args.output)
    report.write(run, report_path)
    say(report.summary(run))
    return status


if __name__ == "__main__":
    sys.exit(main())
