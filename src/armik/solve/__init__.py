"""Solving: single solves with their prepared cache, batches, paths, a Dask cluster,
progress and reachability maps. Every answer passes through ``armik.verify``."""
