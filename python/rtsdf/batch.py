"""Batch bakes on Dask distributed: many meshes, or one scene by tiles, each task a native bake on a worker.

    python3 -m rtsdf.batch INPUT... -o DIR [--workers N | --scheduler tcp://HOST:8786] [--method M --res R ...]

INPUT: mesh or scene files, folders (their mesh files, recursively), globs, or manifests (.jsonl: one JSON object a
line, {"input": path, "name": stem, "samples": n, and any bake setting}, paths relative to the manifest). Each item
becomes DIR/NAME.vdb (and DIR/NAME.npz of sample points with signed distances when samples > 0), written atomically
by this process, and a row of DIR/manifest.jsonl (appended and fsynced). A rerun skips the items whose content hash
(mesh bytes and settings) and outputs match a done row. run() is the same from Python.
"""
import argparse
import glob
import hashlib
import json
import logging
import os
import signal
import socket
import sys
import tempfile
import threading
import time

MESH_SUFFIXES = (".obj", ".ply", ".stl", ".off", ".gltf", ".glb", ".fbx", ".dae", ".3ds", ".json")
# Mesh formats held in one file: their bytes travel with the task, so workers need not see the client's files.
SELF_CONTAINED = (".obj", ".ply", ".stl", ".off", ".glb")
GPU_METHODS = ("jfa", "rtsdf")
MANIFEST = "manifest.jsonl"


# ---------------------------------------------------------------------------------------------------------------
# Items: what to bake, named and hashed on the client.

def _one_line(error):
    text = f"{type(error).__name__}: {error}" if not str(error).startswith(type(error).__name__) else str(error)
    return " ".join(text.split())[:500]


def _mesh_files(folder):
    found = []
    for root, dirs, files in os.walk(folder):
        dirs.sort()
        found += [os.path.join(root, f) for f in sorted(files) if f.lower().endswith(MESH_SUFFIXES)]
    return found


def _manifest_items(path):
    items = []
    base = os.path.dirname(os.path.abspath(path))
    with open(path) as f:
        for number, line in enumerate(f, 1):
            if not line.strip():
                continue
            try:
                row = json.loads(line)
                source = row.pop("input")
            except (ValueError, KeyError, AttributeError, TypeError):
                raise ValueError(f"{path}:{number}: not a JSON object with an \"input\" key")
            items.append((os.path.join(base, source), row))
    return items


def expand_inputs(inputs):
    """(path, per-item settings) of every input: files, folders, globs and .jsonl manifests, in order."""
    items = []
    for entry in inputs:
        if entry.endswith(".jsonl") and os.path.isfile(entry):
            items += _manifest_items(entry)
        elif os.path.isdir(entry):
            items += [(p, {}) for p in _mesh_files(entry)]
        elif any(c in entry for c in "*?[") and not os.path.exists(entry):
            items += [(p, {}) for p in sorted(glob.glob(entry, recursive=True)) if os.path.isfile(p)]
        else:
            items.append((entry, {}))  # a missing file is a failed row, not the end of the batch
    return items


def _stem(path):
    return os.path.splitext(os.path.basename(path))[0] or "item"


def make_items(inputs, settings, samples, ship=False):
    """The batch's items: input, output name (unique in DIR), settings, samples and content hash; with ship, the
    bytes of single-file meshes too (for workers that do not see the client's files)."""
    expanded = expand_inputs(inputs)
    stems = {}
    for path, row in expanded:
        stems.setdefault(row.get("name") or _stem(path), set()).add(os.path.abspath(path))
    items = []
    for path, row in expanded:
        row = dict(row)
        name = row.pop("name", None) or _stem(path)
        if len(stems[name]) > 1:  # two inputs with one stem: the path tells them apart
            name = f"{name}-{hashlib.sha1(os.path.abspath(path).encode()).hexdigest()[:8]}"
        item_samples = int(row.pop("samples", samples))
        item = {"input": path, "path": os.path.abspath(path), "name": name, "settings": {**settings, **row},
                "samples": item_samples}
        try:
            with open(path, "rb") as f:
                data = f.read()
            h = hashlib.sha256(data)
            h.update(json.dumps([item["settings"], item_samples], sort_keys=True).encode())
            item["hash"] = h.hexdigest()
            item["bytes"] = data if ship and path.lower().endswith(SELF_CONTAINED) else None
        except OSError as e:
            item["hash"], item["bytes"], item["error"] = "", None, f"{path}: {e.strerror or e}"
        items.append(item)
    seen = set()
    for item in items:
        if item["name"] in seen:
            raise ValueError(f"{item['input']}: output name '{item['name']}' is given twice")
        seen.add(item["name"])
    return items


# ---------------------------------------------------------------------------------------------------------------
# Tasks: what a worker runs.

_threads_set = False


def _worker_setup():
    """The worker's identity, and its thread count handed to the library once per process."""
    global _threads_set
    from . import _rtsdf
    try:
        from distributed import get_worker
        worker = get_worker()
        address = worker.address
        threads = worker.state.nthreads if hasattr(worker, "state") else worker.nthreads
    except (ImportError, ValueError, AttributeError):
        address, threads = f"{socket.gethostname()}:{os.getpid()}", 0
    if not _threads_set:
        _rtsdf.set_threads(threads)
        _threads_set = True
    return _rtsdf, address


def _mesh_path(item, folder):
    """The input where this worker sees it, else the bytes the task carried, written into folder."""
    if item.get("bytes") is None or os.path.isfile(item["path"]):
        return item["path"]
    path = os.path.join(folder, os.path.basename(item["path"]))
    with open(path, "wb") as f:
        f.write(item["bytes"])
    return path


def _bake_settings(settings):
    s = dict(settings)
    return s.pop("method", "exact"), int(s.pop("res", 128)), _length(s.pop("band", None)), s


def _length(value):
    """A band as rtsdf reads it: None (the default, 6 voxels), a number in scene units or a string such as "3vox"."""
    if value is None or isinstance(value, (int, float)):
        return value
    try:
        return float(value)
    except ValueError:
        return str(value)


def _samples(rtsdf, scene, field, n, seed):
    """n uniform points in the grid's box and n near the surface (active voxels, jittered), exact distances."""
    import io
    import numpy as np
    rng = np.random.default_rng(seed)
    origin, h = np.array(field.origin), field.voxel_size
    active = np.argwhere(field.active)
    extent = np.array(field.active.shape) * h
    uniform = origin + rng.random((n, 3)) * extent
    near = origin + (active[rng.integers(0, len(active), n)] + rng.random((n, 3))) * h
    buffer = io.BytesIO()
    np.savez_compressed(buffer, uniform_points=uniform.astype(np.float32),
                        uniform_sdf=rtsdf.distance(scene, uniform), near_points=near.astype(np.float32),
                        near_sdf=rtsdf.distance(scene, near))
    return buffer.getvalue()


def _active_voxels(rtsdf, path, field):
    try:
        import pyopenvdb
        return int(pyopenvdb.readAllGridMetadata(path)[0]["file_voxel_count"])
    except (ImportError, KeyError, IndexError, RuntimeError):
        return int(field.active.sum())


def bake_item(item):
    """Bake one item on a worker: the .vdb (and .npz) bytes and the counts, or the one-line error. Never raises."""
    start, cpu = time.perf_counter(), time.process_time()
    rtsdf, worker = _worker_setup()
    result, shipped = {"worker": worker}, None
    try:
        if item.get("error"):
            raise OSError(item["error"])
        method, res, band, extra = _bake_settings(item["settings"])
        with tempfile.TemporaryDirectory(prefix="rtsdf-batch-") as folder:
            shipped = _mesh_path(item, folder)
            scene = rtsdf.load_scene(shipped)
            # progress=None: the bake reports nothing (the batch's own progress counts the items)
            field = rtsdf.bake(scene, method=method, res=res, band=band, progress=None, **extra)
            out = os.path.join(folder, item["name"] + ".vdb")
            field.write(out)
            with open(out, "rb") as f:
                result["vdb"] = f.read()
            result["active_voxels"] = _active_voxels(rtsdf, out, field)
            result["triangles"] = scene.triangles
            if item["samples"] > 0:
                result["npz"] = _samples(rtsdf, scene, field, item["samples"], int(item["hash"][:15], 16))
        result["status"] = "done"
    except Exception as e:  # a bad mesh or setting is this item's failure, not the batch's
        error = _one_line(e)
        if shipped:  # the library names the file it read: name the input as given
            error = error.replace(shipped, item["input"])
        result.update(status="failed", error=error)
    result["seconds"], result["cpu_seconds"] = time.perf_counter() - start, time.process_time() - cpu
    return result


def bake_tile(item, tile, tiles):
    """Bake one tile of an item's exact bake on a worker: the tile's .vdb bytes and counts (raises on error)."""
    cpu = time.process_time()
    rtsdf, worker = _worker_setup()
    method, res, band, extra = _bake_settings(item["settings"])
    if method != "exact":
        raise ValueError(f"--tiles bakes with the exact method, not {method}")
    with tempfile.TemporaryDirectory(prefix="rtsdf-tile-") as folder:
        out = os.path.join(folder, f"tile{tile}.vdb")
        info = rtsdf.bake_tile(_mesh_path(item, folder), out, tile, tiles, res=res, band=band, **extra)
        with open(out, "rb") as f:
            info["vdb"] = f.read()
    info["worker"], info["cpu_seconds"] = worker, time.process_time() - cpu
    return info


# ---------------------------------------------------------------------------------------------------------------
# The client: outputs, manifest, progress.

def _sha256_file(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _write_atomic(path, data):
    """Write data to path through a temporary file beside it, fsynced, then renamed: whole or absent."""
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp", dir=os.path.dirname(path))
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


class Manifest:
    """DIR/manifest.jsonl: one row per item and run, each appended in one write and fsynced."""

    def __init__(self, folder):
        self.path = os.path.join(folder, MANIFEST)
        self.finished = {}  # name -> the last done or cached row
        if os.path.exists(self.path):
            with open(self.path) as f:
                for line in f:
                    try:
                        row = json.loads(line)
                    except ValueError:
                        continue  # a row cut by a crash of the machine: its item is baked again
                    if row.get("status") in ("done", "cached"):
                        self.finished[row["name"]] = row
        self.fd = os.open(self.path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)

    def cached(self, item, folder):
        """The finished row of item when its hash and every output still match, else None."""
        row = self.finished.get(item["name"])
        if not row or not item["hash"] or row.get("hash") != item["hash"]:
            return None
        for kind, name in row.get("outputs", {}).items():
            path = os.path.join(folder, name)
            if not os.path.isfile(path) or _sha256_file(path) != row.get("sha256", {}).get(kind):
                return None
        return row

    def append(self, row):
        os.write(self.fd, (json.dumps(row, sort_keys=True) + "\n").encode())
        os.fsync(self.fd)

    def close(self):
        os.close(self.fd)


class Progress:
    """A bar on a terminal, a line per item otherwise, and the closing summary."""

    def __init__(self, total, stream=None):
        self.total, self.stream = total, stream or sys.stderr
        self.bar = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.counts = {"done": 0, "cached": 0, "failed": 0}
        self.start = time.monotonic()

    def rate(self):
        minutes = (time.monotonic() - self.start) / 60.0
        return self.counts["done"] / minutes if minutes > 0 else 0.0

    def row(self, row):
        self.counts[row["status"]] += 1
        n = sum(self.counts.values())
        if self.bar:
            if row["status"] == "failed":  # above the bar, which is drawn again below it
                self.stream.write(f"\r\033[Krtsdf.batch: failed {row['name']}: {row.get('error')}\n")
            filled = int(30 * n / max(self.total, 1))
            self.stream.write(f"\r[{'#' * filled}{'.' * (30 - filled)}] {n}/{self.total} done {self.counts['done']} "
                              f"cached {self.counts['cached']} failed {self.counts['failed']} "
                              f"{self.rate():.1f}/min ")
        else:
            detail = row.get("error") if row["status"] == "failed" else f"{row.get('seconds', 0.0):.2f} s"
            self.stream.write(f"rtsdf.batch: {n}/{self.total} {row['status']} {row['name']} ({detail})\n")
        self.stream.flush()

    def summary(self, interrupted=False):
        seconds = time.monotonic() - self.start
        c = self.counts
        text = (f"rtsdf.batch: {sum(c.values())} of {self.total} items: {c['done']} done, {c['cached']} cached, "
                f"{c['failed']} failed in {seconds:.1f} s ({self.rate():.1f} meshes/minute)"
                + ("; interrupted, rerun to finish" if interrupted else ""))
        self.stream.write(("\n" if self.bar else "") + text + "\n")
        self.stream.flush()
        return {**c, "total": self.total, "seconds": seconds, "meshes_per_minute": self.rate(),
                "interrupted": interrupted}


class _Deferred:
    """Ctrl-C held back while an item's outputs and row are written, raised right after (main thread only: the
    only one Python delivers signals to)."""

    def __enter__(self):
        self.caught, self.previous = False, None
        # Only Python's own Ctrl-C (KeyboardInterrupt) is held back: an ignored SIGINT stays ignored.
        if threading.current_thread() is threading.main_thread() and \
                signal.getsignal(signal.SIGINT) is signal.default_int_handler:
            self.previous = signal.signal(signal.SIGINT, self._hold)
        return self

    def _hold(self, signum, frame):
        self.caught = True

    def __exit__(self, kind, value, trace):
        if self.previous is not None:
            signal.signal(signal.SIGINT, self.previous)
            if self.caught and kind is None:
                raise KeyboardInterrupt


def _finish(item, result, folder, manifest, progress, on_row):
    row = {"input": item["input"], "name": item["name"], "hash": item["hash"], "settings": item["settings"],
           "status": result["status"], "seconds": round(result.get("seconds", 0.0), 4),
           "cpu_seconds": round(result.get("cpu_seconds", 0.0), 4),
           "worker": result.get("worker", ""), "triangles": result.get("triangles"),
           "active_voxels": result.get("active_voxels"), "outputs": {}, "sha256": {}, "error": result.get("error"),
           "time": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    if "tiles" in result:
        row["tiles"] = result["tiles"]
    with _Deferred():
        for kind in ("vdb", "npz"):
            if result.get(kind) is not None:
                name = f"{item['name']}.{kind}"
                _write_atomic(os.path.join(folder, name), result[kind])
                row["outputs"][kind], row["sha256"][kind] = name, hashlib.sha256(result[kind]).hexdigest()
        if result.get("written"):  # a merged tiled bake, already in place
            name = f"{item['name']}.vdb"
            row["outputs"]["vdb"], row["sha256"]["vdb"] = name, _sha256_file(os.path.join(folder, name))
        manifest.append(row)
    progress.row(row)
    if on_row:
        on_row(row)


def _cluster(client, scheduler, workers, threads_per_worker, gpu):
    """(client, closer): the given client, one connected to `scheduler`, or a local cluster this run owns."""
    from distributed import Client, LocalCluster
    if client is not None:
        return client, lambda: None
    if scheduler:
        c = Client(scheduler, direct_to_workers=True)
        return c, c.close
    import dask
    dask.config.set({"distributed.scheduler.allowed-failures": 2})
    cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=threads_per_worker,
                           processes=True, dashboard_address=":0", silence_logs=logging.ERROR,
                           resources={"GPU": 1} if gpu else None)
    c = Client(cluster, direct_to_workers=True)

    def close():
        c.close()
        cluster.close()
    return c, close


def _bake_items(client, items, folder, manifest, progress, on_row, gpu):
    """Submit the items a window at a time (memory stays bounded, Ctrl-C cancels little) and finish each as it ends."""
    from distributed import as_completed
    window = max(4, 3 * max(1, sum(client.nthreads().values())))
    pending = list(reversed(items))
    running = {}
    done = as_completed()

    def submit():
        while pending and len(running) < window:
            item = pending.pop()
            future = client.submit(bake_item, item, key=f"bake-{item['name']}-{item['hash'][:12]}", pure=False,
                                   resources={"GPU": 1} if gpu else None)
            running[future.key] = item
            done.add(future)
    submit()
    for future in done:
        item = running.pop(future.key)
        try:
            result = future.result()
        except Exception as e:  # e.g. KilledWorker: the item crashed its workers as often as allowed
            result = {"status": "failed", "error": _one_line(e)}
        future.release()
        _finish(item, result, folder, manifest, progress, on_row)
        submit()


def _bake_tiled(client, items, tiles, folder, manifest, progress, on_row):
    """Each item by tiles: its tiles baked on the workers at once, merged here into DIR/NAME.vdb."""
    from . import _rtsdf
    for item in items:
        start = time.perf_counter()
        futures = [client.submit(bake_tile, item, t, tiles, key=f"tile-{item['name']}-{item['hash'][:12]}-{t}",
                                 pure=False) for t in range(tiles)]
        try:
            parts = client.gather(futures)
            out = os.path.join(folder, item["name"] + ".vdb")
            with _Deferred():
                merged = _rtsdf.merge_tiles([p["vdb"] for p in parts], out)
            result = {"status": "done", "written": True, "active_voxels": merged["active_voxels"],
                      "triangles": parts[0]["triangles"], "tiles": tiles,
                      "cpu_seconds": sum(p["cpu_seconds"] for p in parts),
                      "worker": ",".join(sorted({p["worker"] for p in parts}))}
        except Exception as e:
            result = {"status": "failed", "error": _one_line(e)}
        result["seconds"] = time.perf_counter() - start
        _finish(item, result, folder, manifest, progress, on_row)


def run(inputs, out_dir, *, workers=None, scheduler=None, client=None, threads_per_worker=1, method="exact",
        res=128, band=None, samples=0, tiles=0, settings=None, ship=None, stream=None, on_row=None):
    """Bake every input into out_dir on Dask; returns the summary (done, cached, failed, meshes_per_minute ...).

    workers: processes of the local cluster (default: one per core) when neither scheduler (an address such as
    tcp://host:8786) nor client (a distributed.Client) is given. settings: further bake keywords (rtsdf.bake's).
    samples: points per kind (uniform, near the surface) in DIR/NAME.npz. tiles: bake each item by this many tiles
    (exact method). ship: send the bytes of single-file meshes with their tasks (default: with a scheduler
    address, not to a local cluster or a given client, whose workers read the client's files). on_row(row) is
    called after each manifest row. KeyboardInterrupt propagates after the cluster this run started is closed;
    every row written stands.
    """
    if isinstance(inputs, (str, os.PathLike)):
        inputs = [inputs]
    settings = {"method": method, "res": res, "band": band, **(settings or {})}
    if tiles and samples:
        raise ValueError("samples are not drawn in a tiled bake (give either --tiles or --samples)")
    if tiles and settings["method"] != "exact":
        raise ValueError(f"--tiles bakes with the exact method, not {settings['method']}")
    os.makedirs(out_dir, exist_ok=True)
    items = make_items([os.fspath(i) for i in inputs], settings, samples, bool(scheduler) if ship is None else ship)
    manifest = Manifest(out_dir)
    progress = Progress(len(items), stream)
    interrupted = False
    close = None
    try:
        todo = []
        for item in items:
            row = manifest.cached(item, out_dir)
            if row is None:
                todo.append(item)
                continue
            cached = {**row, "status": "cached", "seconds": 0.0, "cpu_seconds": 0.0, "worker": "",
                      "input": item["input"], "time": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
            manifest.append(cached)
            progress.row(cached)
            if on_row:
                on_row(cached)
        if todo:
            gpu = any(i["settings"].get("method") in GPU_METHODS for i in todo)
            client, close = _cluster(client, scheduler, workers, threads_per_worker, gpu)
            offered = [w.get("resources", {}).get("GPU", 0) for w in client.scheduler_info()["workers"].values()]
            if gpu and not any(offered):
                raise ValueError("the GPU methods need workers that offer the resource GPU (dask worker ... "
                                 "--resources GPU=1); none of this cluster's does")
            if tiles:
                _bake_tiled(client, todo, tiles, out_dir, manifest, progress, on_row)
            else:
                _bake_items(client, todo, out_dir, manifest, progress, on_row, gpu)
    except KeyboardInterrupt:
        interrupted = True
        raise
    finally:
        manifest.close()
        if close:
            try:
                close()
            except Exception:
                pass
        summary = progress.summary(interrupted)
    return summary


# ---------------------------------------------------------------------------------------------------------------
# The command line.

def _setting(text):
    key, sep, value = text.partition("=")
    if not sep or not key:
        raise argparse.ArgumentTypeError(f"--set '{text}': give KEY=VALUE (a bake keyword, docs/settings.md)")
    try:
        return key, json.loads(value)
    except ValueError:
        return key, value


def parse_args(argv):
    p = argparse.ArgumentParser(prog="python3 -m rtsdf.batch", description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("inputs", nargs="+", metavar="INPUT", help="mesh or scene files, folders, globs, .jsonl manifests")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="folder of the outputs and manifest.jsonl")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N", help="local worker processes (default: one per core)")
    where.add_argument("--scheduler", metavar="ADDR", help="an existing cluster's scheduler, e.g. tcp://host:8786")
    p.add_argument("--threads-per-worker", type=int, default=1, metavar="T", help="threads of each local worker")
    p.add_argument("-m", "--method", default="exact", choices=["exact", "openvdb", "jfa", "rtsdf"])
    p.add_argument("-r", "--res", type=int, default=128, help="voxels across the longest side")
    p.add_argument("--band", default=None,
                   help="narrow band half-width [d]: scene units (0.02) or voxels (3vox); default: bake's, 6 voxels")
    p.add_argument("--set", dest="settings", type=_setting, action="append", default=[], metavar="KEY=VALUE",
                   help="any other bake keyword (docs/settings.md), e.g. --set sign=winding --set padding=0.05")
    p.add_argument("--samples", type=int, default=0, metavar="N",
                   help="write NAME.npz: N uniform points and N near the surface with their signed distances")
    p.add_argument("--no-ship", dest="ship", action="store_false", default=None,
                   help="with --scheduler: the workers read the inputs at the same paths (a shared folder) instead of "
                        "receiving the bytes of single-file meshes with their tasks")
    p.add_argument("--tiles", type=int, default=0, metavar="N",
                   help="bake each input as N tiles on the workers, merged into one .vdb (exact method)")
    args = p.parse_args(argv)
    for flag, value in (("--workers", args.workers), ("--threads-per-worker", args.threads_per_worker),
                        ("--res", args.res)):
        if value is not None and value < 1:
            p.error(f"{flag} {value} must be at least 1")
    for flag, value in (("--samples", args.samples), ("--tiles", args.tiles)):
        if value < 0:
            p.error(f"{flag} {value} must not be negative")
    if args.band is not None:
        text = args.band[:-3] if args.band.endswith("vox") else args.band
        try:
            positive = float(text) > 0
        except ValueError:
            positive = False
        if not positive:
            p.error(f"--band {args.band} must be a positive length in scene units (0.02) or voxels (3vox)")
        args.band = _length(args.band)
    return args


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        summary = run(args.inputs, args.output, workers=args.workers, scheduler=args.scheduler,
                      threads_per_worker=args.threads_per_worker, method=args.method, res=args.res, band=args.band,
                      samples=args.samples, tiles=args.tiles, settings=dict(args.settings), ship=args.ship)
    except KeyboardInterrupt:
        return 130
    except (ValueError, OSError) as e:
        sys.stderr.write(f"rtsdf.batch: {_one_line(e)}\n")
        return 2
    return 1 if summary["failed"] else 0


if __name__ == "__main__":
    # Run as rtsdf.batch (not __main__), so that the workers find the task functions by their module's name.
    from rtsdf import batch as _batch
    sys.exit(_batch.main())
