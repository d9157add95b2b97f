"""The Dask side: a client on a local cluster or a running scheduler, the
workers asked first whether they can read the inputs, the units submitted
with retries and followed with a progress line."""

import importlib.util
import sys
import time

from . import unit

# Debian 12 packages distributed without bokeh: no dashboard then
HAS_DASHBOARD = importlib.util.find_spec("bokeh") is not None


def ship_by_value():
    """The functions a unit runs travel with it (cloudpickle by value), so a worker needs QGIS, GeoStation's
    plugin and Dask, but not this package on its Python path."""
    import cloudpickle
    from . import qgis
    for module in (unit, qgis):
        cloudpickle.register_pickle_by_value(module)


def connect(scheduler, workers, say):
    """A client: on `scheduler` (an address), or on a local cluster of `workers` processes."""
    from distributed import Client, LocalCluster
    if scheduler:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as e:
            raise ConnectionError("no Dask scheduler answers at %s (%s): start one with dask-scheduler, or leave out --scheduler" % (scheduler, e))
        cluster = None
    else:
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                               dashboard_address=":0" if HAS_DASHBOARD else None, silence_logs=40)
        client = Client(cluster)
    ship_by_value()
    say("Dask scheduler %s with %d workers" % (client.scheduler.address, len(client.scheduler_info()["workers"])))
    if HAS_DASHBOARD and client.dashboard_link:
        say("Dashboard: %s" % client.dashboard_link)
    else:
        say("Dashboard: none (bokeh is not installed; Debian 12 does not package it)")
    return client, cluster


def check_workers(client, paths, work_dir, executable, qgis_home, say):
    """Asks every worker whether it can read the inputs, write the work dir and run qgis_process with
    GeoStation; a worker that cannot is named and left out. Returns the workers kept."""
    answers = client.run(unit.check_access, paths, work_dir, executable, qgis_home)
    bad = {address: problems for address, problems in answers.items() if problems}
    for address, problems in sorted(bad.items()):
        say("Worker %s %s (a cluster needs the block, images, DEM and work dir on a file system every node sees, "
            "and GeoStation installed on every node): it is left out of this run." % (address, "; ".join(problems)))
    if bad:
        client.retire_workers(workers=list(bad), close_workers=True)
    return sorted(set(answers) - set(bad))


class Progress:
    """One line: units done of total, failed, time left (rewritten in place on a terminal)."""

    def __init__(self, total, skipped, stream=sys.stderr):
        self.total, self.done, self.failed, self.skipped = total, skipped, 0, skipped
        self.start = time.time()
        self.stream = stream
        self.tty = stream.isatty()
        self.last = 0.0

    def update(self, failed=False, final=False):
        if failed:
            self.failed += 1
        else:
            self.done += 1
        now = time.time()
        if not final and not self.tty and now - self.last < 10.0 and self.done + self.failed < self.total:
            return
        self.last = now
        ran = self.done - self.skipped + self.failed
        left = self.total - self.done - self.failed
        eta = "%.0f s left" % ((now - self.start) / ran * left) if ran and left else ("done" if not left else "")
        width = 30
        filled = int(width * (self.done + self.failed) / max(1, self.total))
        line = "[%s%s] %d of %d units, %d failed, %s" % ("#" * filled, "." * (width - filled), self.done, self.total, self.failed, eta)
        self.stream.write(("\r" + line + " " * 8) if self.tty else line + "\n")
        if self.tty and left == 0:
            self.stream.write("\n")
        self.stream.flush()


def run_units(client, pending, done_before, total, work_dir, executable, qgis_home, retries, timeout):
    """Runs the units not yet complete (`pending`; `done_before` of `total` are); returns ({id: manifest entry}, {id: error sentence})."""
    from distributed import as_completed
    entries, errors = {}, {}
    progress = Progress(total, done_before)
    futures = {}
    for spec in pending:
        future = client.submit(unit.run_unit, spec, work_dir, executable, qgis_home, timeout,
                               key="geostation-%s-%s" % (spec["id"], spec["digest"]), retries=retries, pure=False)
        futures[future] = spec["id"]
    for future in as_completed(futures):
        unit_id = futures[future]
        if future.status == "finished":
            entries[unit_id] = future.result()
            progress.update()
        else:
            try:
                error = future.exception()
            except Exception as e:  # cancelled: the scheduler dropped it
                error = e
            errors[unit_id] = str(error) or type(error).__name__
            if type(error).__name__ == "KilledWorker":
                errors[unit_id] = "its worker died every time it ran it (%s)" % error
            elif future.status == "cancelled":
                errors[unit_id] = "the scheduler cancelled it (was it restarted?); run the command again to run it"
            progress.update(failed=True)
    return entries, errors
