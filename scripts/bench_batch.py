#!/usr/bin/env python3
"""Measure rtsdf.batch: meshes per minute with 1 and 2 single-threaded workers and 1 worker of 2 threads, the
per-item overhead against single `rtsdf bake` commands of the same meshes, and a tiled bake against the whole one.

    PYTHONPATH=build/python /usr/bin/python3 scripts/bench_batch.py [--meshes 200] [--res 64] [--tiles 8]
        [--tile-res 512] [--rtsdf build/apps/rtsdf/rtsdf] [--work /tmp/rtsdf-bench-batch]

Meshes: generated bumpy spheres (icosphere of 5120 triangles, radial noise), one per item. Each configuration runs
on a local cluster started beforehand (its start-up timed apart) into an empty folder. The overhead anchor is the
`rtsdf bake` command of the same mesh at the same settings pinned to one core (taskset), the work of one
single-threaded worker's task. Prints a Markdown table for docs/results.md.
"""
import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import time

import numpy as np

import rtsdf
import rtsdf.batch as batch
from distributed import Client, LocalCluster

# The test suite's mesh generator: the benchmark bakes the meshes the batch tests bake.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "python"))
from meshgen import icosphere  # noqa: E402


def generate(folder, count):
    os.makedirs(folder, exist_ok=True)
    verts, faces = icosphere(4)
    rng = np.random.default_rng(1)
    paths = []
    for i in range(count):
        k = rng.normal(size=(3, 3))
        bumps = 1.0 + 0.08 * np.sin(verts @ k).sum(axis=1)
        path = os.path.join(folder, f"mesh{i:04d}.obj")
        with open(path, "w") as f:
            f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in verts * bumps[:, None])
            f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
        paths.append(path)
    return paths


def batch_run(paths, out, workers, threads, res, band):
    shutil.rmtree(out, ignore_errors=True)
    start = time.perf_counter()
    with LocalCluster(n_workers=workers, threads_per_worker=threads, processes=True, dashboard_address=":0") as c:
        with Client(c, direct_to_workers=True) as client:
            client.run(lambda: 0)
            started = time.perf_counter() - start
            client.run(lambda: __import__("rtsdf"))
            t0, cpu0 = time.perf_counter(), time.process_time()
            summary = batch.run(paths, out, client=client, res=res, band=band, stream=open(os.devnull, "w"))
            seconds, client_cpu = time.perf_counter() - t0, time.process_time() - cpu0
    assert summary["done"] == len(paths), summary
    with open(os.path.join(out, "manifest.jsonl")) as f:
        rows = [json.loads(line) for line in f]
    vdb_bytes = sum(os.path.getsize(os.path.join(out, r["outputs"]["vdb"])) for r in rows)
    mesh_bytes = sum(os.path.getsize(p) for p in paths)
    return {"workers": workers, "threads": threads, "seconds": seconds, "startup": started,
            "per_minute": 60.0 * len(paths) / seconds, "client_cpu": client_cpu / len(paths),
            "worker_cpu": sum(r["cpu_seconds"] for r in rows) / len(paths),
            "worker_wall": sum(r["seconds"] for r in rows) / len(paths),
            "bytes_in": mesh_bytes / len(paths), "bytes_out": vdb_bytes / len(paths)}


def cli_bake(binary, path, out, res, band):
    """Wall and CPU seconds of one `rtsdf bake` command on one core."""
    t0, r0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(["taskset", "-c", "0", binary, "-q", "bake", path, "--method", "exact", "--res", str(res),
                    "--band", str(band), "-o", out], check=True, stdout=subprocess.DEVNULL)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.perf_counter() - t0, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--meshes", type=int, default=200)
    p.add_argument("--res", type=int, default=64)
    p.add_argument("--band", type=float, default=0.1)
    p.add_argument("--tiles", type=int, default=8)
    p.add_argument("--tile-res", type=int, default=512)
    p.add_argument("--rtsdf", default="build/apps/rtsdf/rtsdf")
    p.add_argument("--work", default="/tmp/rtsdf-bench-batch")
    p.add_argument("--skip", nargs="*", default=[], choices=["batch", "overhead", "tiles"])
    a = p.parse_args()
    print(f"machine: {os.cpu_count()} cores; load before: {os.getloadavg()}")
    paths = generate(os.path.join(a.work, "meshes"), a.meshes)
    runs = []
    if "batch" not in a.skip:
        for workers, threads in ((1, 1), (2, 1), (1, 2)):
            runs.append(batch_run(paths, os.path.join(a.work, f"out{workers}x{threads}"), workers, threads, a.res,
                                  a.band))
            r = runs[-1]
            print(f"{workers} worker(s) x {threads} thread(s): {r['seconds']:.1f} s, {r['per_minute']:.1f} meshes/min "
                  f"(cluster start {r['startup']:.1f} s); per item: worker {r['worker_wall'] * 1000:.1f} ms wall, "
                  f"{r['worker_cpu'] * 1000:.1f} ms CPU, client and scheduler {r['client_cpu'] * 1000:.1f} ms CPU; "
                  f"mesh {r['bytes_in'] / 1024:.0f} KiB in, .vdb {r['bytes_out'] / 1024:.0f} KiB out; "
                  f"load {os.getloadavg()[0]:.1f}", flush=True)
        print(f"2 workers / 1 worker: {runs[1]['per_minute'] / runs[0]['per_minute']:.2f}x; "
              f"1 worker of 2 threads / 1 worker: {runs[2]['per_minute'] / runs[0]['per_minute']:.2f}x; "
              f"workers one client keeps busy (worker CPU / client CPU per item, 1 worker): "
              f"{runs[0]['worker_cpu'] / runs[0]['client_cpu']:.0f}")
    if "overhead" not in a.skip:
        sample = paths[:: max(1, len(paths) // 20)]
        cli = [cli_bake(a.rtsdf, path, os.path.join(a.work, "cli.vdb"), a.res, a.band) for path in sample]
        wall, cpu = statistics.median(c[0] for c in cli), statistics.median(c[1] for c in cli)
        print(f"rtsdf bake (1 core), median of {len(sample)}: {wall * 1000:.1f} ms wall, {cpu * 1000:.1f} ms CPU; "
              f"load {os.getloadavg()[0]:.1f}")
        if runs:
            r = runs[0]
            per_item = r["seconds"] / len(paths)
            print(f"batch, 1 single-threaded worker: {per_item * 1000:.1f} ms wall per item: "
                  f"{100 * (per_item / wall - 1):+.1f}% of a single bake's wall; "
                  f"{(r['worker_cpu'] + r['client_cpu']) * 1000:.1f} ms CPU (worker + client): "
                  f"{100 * ((r['worker_cpu'] + r['client_cpu']) / cpu - 1):+.1f}% of its CPU")
    if "tiles" not in a.skip:
        bunny = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "scenes", "bunny.json")
        scene = rtsdf.load_scene(bunny)
        whole_path = os.path.join(a.work, "whole.vdb")
        band = 3.0 * 2.0 / a.tile_res  # 3 voxels: the scene is about 2 units across
        rtsdf.set_threads(2)
        t0 = time.perf_counter()
        rtsdf.bake(scene, method="exact", res=a.tile_res, band=band).write(whole_path)
        whole = time.perf_counter() - t0
        print(f"whole bake, bunny at {a.tile_res} (band {band:.4g}), 1 process of 2 threads: {whole:.1f} s", flush=True)
        out = os.path.join(a.work, "tiled")
        shutil.rmtree(out, ignore_errors=True)
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as c:
            with Client(c, direct_to_workers=True) as client:
                client.run(lambda: 0)
                t0 = time.perf_counter()
                batch.run([bunny], out, client=client, res=a.tile_res, band=band, tiles=a.tiles,
                          stream=open(os.devnull, "w"))
                tiled = time.perf_counter() - t0
        differ = rtsdf.count_different_values(whole_path, os.path.join(out, "bunny.vdb"))
        print(f"tiled bake, {a.tiles} tiles on 2 single-threaded workers: {tiled:.1f} s ({whole / tiled:.2f}x of "
              f"the whole bake); values that differ: {differ}")
        if differ:
            sys.exit(1)
    print(f"load after: {os.getloadavg()}")


if __name__ == "__main__":
    main()
