"""The run report: JSON for machines, a few lines for a person."""

import json
import os
import time

from . import unit


class Run:
    def __init__(self, command, algorithm, work_dir, start_up_seconds):
        self.command, self.algorithm, self.work_dir = command, algorithm, work_dir
        self.start_up_seconds = start_up_seconds  # one qgis_process start (its help), the cost each unit pays
        self.started = time.time()
        self.workers = 0
        self.unit_rows, self.failed = [], {}
        self.merge, self.merge_error = None, None
        self.status, self.output, self.wall_seconds = None, None, None

    def units(self, specs, entries, errors):
        for spec in specs:
            entry = entries.get(spec["id"])
            if entry:
                self.unit_rows.append({"id": spec["id"], "seconds": round(entry.get("seconds", 0.0), 3), "worker": entry.get("worker"),
                                       "peak_rss_mb": entry.get("peak_rss_mb"), "resumed": bool(entry.get("skipped"))})
        self.failed = dict(sorted(errors.items()))

    def finish(self, status, output):
        self.status, self.output = status, output
        self.wall_seconds = time.time() - self.started

    def as_json(self):
        ran = [u for u in self.unit_rows if not u["resumed"]]
        seconds = sorted(u["seconds"] for u in ran)
        return {
            "command": self.command, "algorithm": self.algorithm, "output": self.output, "work_dir": self.work_dir,
            "exit_status": self.status, "partial": self.status != 0, "workers": self.workers,
            "units": len(self.unit_rows) + len(self.failed), "units_done": len(self.unit_rows), "units_run": len(ran),
            "units_resumed": len(self.unit_rows) - len(ran), "units_failed": len(self.failed),
            "failed": [{"id": k, "error": v} for k, v in self.failed.items()],
            "unit_seconds": {"total": round(sum(seconds), 3), "median": seconds[len(seconds) // 2] if seconds else None,
                             "max": seconds[-1] if seconds else None},
            "qgis_process_start_seconds": round(self.start_up_seconds, 3),
            "peak_rss_mb": max((u["peak_rss_mb"] or 0.0 for u in ran), default=None),
            "start_up_share": round(self.start_up_seconds / seconds[len(seconds) // 2], 3) if seconds and seconds[len(seconds) // 2] > 0 else None,
            "per_unit": self.unit_rows,
            "merge": self.merge, "merge_error": self.merge_error,
            "wall_seconds": round(self.wall_seconds, 3) if self.wall_seconds is not None else None,
        }


def summary(run):
    r = run.as_json()
    lines = ["%s: %d of %d units done (%d run now, %d from an earlier run), %d failed, in %.0f s on %d workers." %
             (r["command"], r["units_done"], r["units"], r["units_run"], r["units_resumed"], r["units_failed"], r["wall_seconds"], r["workers"])]
    if r["unit_seconds"]["median"] is not None:
        lines.append("A unit took %.1f s (median; longest %.1f s); starting qgis_process takes %.1f s of it; a unit's qgis_process peaked at %.0f MB." %
                     (r["unit_seconds"]["median"], r["unit_seconds"]["max"], r["qgis_process_start_seconds"], r["peak_rss_mb"] or 0.0))
    for f in r["failed"]:
        lines.append("Failed: %s: %s" % (f["id"], f["error"]))
    merged = r["merge"] or {}
    if r["command"] == "extract" and merged:
        lines.append("Merged %d lines of %d pairs into %d: %.0f m dropped as duplicates, %d borders joined, %d junctions." %
                     (merged.get("lines_in", 0), merged.get("pairs", 0), merged.get("lines_out", 0), merged.get("duplicate_length_m", 0.0),
                      merged.get("borders_joined", 0), merged.get("junctions", 0)))
    elif r["command"] == "trace" and merged:
        lines.append("Joined %d pieces into %d lines; %d places where neighbouring pieces disagree beyond 3 sigma or do not meet." %
                     (merged.get("pieces", 0), len(merged.get("lines", [])), len(merged.get("disagreements", []))))
        for d in merged.get("disagreements", []):
            lines.append("  line %s: %s and %s %s" % (d["line_id"], d["first"], d["second"],
                                                       "do not meet (%.2f m apart)" % d["worst_m"] if d["gap"] else
                                                       "are %.3f m apart where they overlap (%.3f m allowed)" % (d["worst_m"], d["allowed_m"])))
    elif r["command"] == "revise" and merged:
        rev = merged.get("revision", {})
        by = rev.get("by_status", {})
        lines.append("Merged %d pieces of %d pairs into %d: %s; %.0f m seen by more than one pair, %.0f m of it with different statuses." %
                     (rev.get("pieces_in", 0), rev.get("pairs", 0), rev.get("pieces_out", 0),
                      ", ".join("%.0f m %s" % (by[s]["map_length_m"], s) for s in sorted(by)) or "nothing",
                      rev.get("seen_twice_m", 0.0), rev.get("disagreed_m", 0.0)))
        if "new" in merged:
            lines.append("New roads: %d lines of the pairs merged into %d." % (merged["new"].get("lines_in", 0), merged["new"].get("lines_out", 0)))
    elif merged:
        lines.append("Merged %d features." % merged.get("features", 0))
    if r["merge_error"]:
        lines.append("Not merged: %s." % r["merge_error"])
    else:
        lines.append("Output: %s%s" % (r["output"], " (partial: the failed units are missing)" if r["partial"] else ""))
    return "\n".join(lines)


def write(run, path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    unit.write_atomically(path, json.dumps(run.as_json(), indent=1))
    text = os.path.splitext(path)[0] + ".txt"
    unit.write_atomically(text, summary(run) + "\n")
