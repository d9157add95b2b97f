"""geostation-batch: GeoStation's Processing algorithms over whole blocks, on Dask distributed.

One unit of work is one ``qgis_process`` run in a subprocess on a worker
(unit.py); the units of a command are planned in plan.py, run through a Dask
client in cluster.py, merged deterministically in merge.py and reported in
report.py. The photogrammetry stays in GeoStation's core, behind the
Processing algorithms; this package only plans, runs, keeps and joins.
"""
