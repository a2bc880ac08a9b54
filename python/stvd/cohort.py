"""Cohort runs: every subject of a manifest, on a Dask cluster, resumable.

``stvd.cohort.run(manifest, outdir)`` (and ``stvd cohort MANIFEST.tsv -o
OUTDIR``, which runs ``main`` below) computes, for each subject of the
manifest (see ``stvd._manifest``), the connectivity between the regions of its
label image and a distance map from each seed set of its seeds table, with
the package's calls and the tool's options. Per subject it writes into
``OUTDIR/<subject>/``:

- ``connectivity.tsv``: the table of ``stvd connectivity``, the same bytes;
- ``distance_<seed set>.nii.gz``: the map of ``stvd distance``;
- ``statistics.json``: what was asked (inputs, options), a summary of each
  part and the size and SHA-256 of each output but the QC page. Written
  last: a subject is complete when it is there, names the same request and
  its outputs have their sizes (and the page is there). It holds nothing
  that depends on where or when the subject ran, so a run on any cluster
  gives the bytes of a serial run;
- ``report.html``: its QC page (``stvd.report``), unless ``report=False``;
  it says when it was made;
- ``run.json``: where and how long it ran, the worker's peak memory and the
  QC page's size and SHA-256;
- ``error.txt``: the one-line error of a subject that failed (and nothing
  else).

``OUTDIR/cohort.tsv`` gathers every subject's summary or error, and
``OUTDIR/index.html`` (with reports) is the cohort index page linking to
every subject's QC page. Every file is
written through the package's ``stvd.OutputFiles`` (staged, flushed and
renamed into place by the library) and no output may be an input. A
re-run skips complete subjects and computes the others again; a subject that
fails is recorded and never stops the others. Workers read and write the
files themselves: only names and small summaries travel through the
scheduler.

What a run removes from a subject's folder: the declared outputs of this
run it rewrites (statistics, run record, error), and the outputs a run of
ours demonstrably wrote there and this request no longer has (a renamed
seed set, the parts of a failed subject) - a file recorded, with its size
and SHA-256, in an earlier run's ``statistics.json`` or ``run.json`` or in
this run's results, still holding those bytes, and no input of any
subject. Never a file by the look of its name.
"""

import argparse
import contextlib
import errno
import fcntl
import json
import logging
import os
import re
import stat
import sys
import tempfile
import time

from . import _core
from ._files import RECORD_BYTES, kind_of, read_regular_text
from ._manifest import PATH_MAX, ManifestError, read_manifest, read_seed_sets
from ._outputs import OutputFiles, check_outputs_are_not_inputs, remove_leftover_staging_folders
from ._subject import (CONNECTIVITY, CONNECTIVITY_FILE, REPORT_FILE, compute_parts, file_record, one_line,
                       output_files)

STATISTICS_FILE = "statistics.json"
RUN_FILE = "run.json"
ERROR_FILE = "error.txt"
COHORT_TABLE = "cohort.tsv"
COHORT_INDEX = "index.html"
LOCK_FILE = ".stvd-cohort.lock"
TABLE_COLUMNS = ("subject", "status", "regions", "pairs_connected", "mean_geodesic_mm", "maps", "map_max_mm",
                 "error")

# The options of the package's calls that a cohort run passes on (None:
# the library's default, stvd.defaults), as the library declares them for
# `stvd cohort`: flag, keyword, kind of value and help with the default.
OPTIONS = tuple(d for d in _core.option_declarations() if "cohort" in d["commands"])
OPTION_NAMES = tuple(d["keyword"] for d in OPTIONS)

__all__ = ["run", "Cohort", "ManifestError", "main"]


class Cohort:
    """What a cohort run did: ``subjects``, one dict per subject in the
    manifest's order (the columns of ``cohort.tsv``, and ``computed``:
    False for a subject complete from an earlier run); ``table``, the path
    of ``cohort.tsv``; ``seconds``; ``workers`` (0 for a serial run);
    ``dashboard`` (Dask's dashboard link, or None); ``index``, the path of
    the cohort index page (None without reports)."""

    def __init__(self, subjects, table, seconds, workers, dashboard, index=None):
        self.subjects, self.table, self.seconds, self.workers, self.dashboard, self.index = (
            subjects, table, seconds, workers, dashboard, index)

    @property
    def failed(self):
        return [s["subject"] for s in self.subjects if s["status"] != "ok"]

    @property
    def computed(self):
        return [s["subject"] for s in self.subjects if s["computed"]]

    def __repr__(self):
        return (f"<stvd.cohort.Cohort of {len(self.subjects)} subjects: {len(self.computed)} computed, "
                f"{len(self.failed)} failed>")


class _Plan:
    """One subject's work in this run: the parts to compute, its seed sets,
    the request its statistics record, and its outputs."""

    def __init__(self, subject, folder, parts, seed_sets, request, error=None):
        self.subject, self.folder, self.parts, self.seed_sets, self.request, self.error = (
            subject, folder, parts, seed_sets, request, error)
        self.report = request["report"]
        self.recorded = {}  # what earlier runs recorded writing in the folder (_start_subject)

    def output_files(self):
        files = {name: os.path.join(self.folder, name) for name in (STATISTICS_FILE, RUN_FILE, ERROR_FILE)}
        files.update({name: path for name, (_, path) in output_files(self.folder, self.parts, self.report).items()})
        return files


def _input_record(path, cell):
    """An input as the statistics record it: the manifest's cell, size and
    modification time (a file replaced under the same name is noticed)."""
    try:
        status = os.stat(path)
        return {"path": cell, "bytes": status.st_size, "mtime_ns": status.st_mtime_ns}
    except OSError:
        return {"path": cell, "bytes": None, "mtime_ns": None}


def _plan(subject, outdir, options, connectivity, maps, report):
    from . import __version__

    folder = os.path.join(outdir, subject.id)
    parts, seed_sets, error = [], {}, None
    if connectivity:
        parts.append(CONNECTIVITY)
    if maps and subject.seeds is not None:
        try:
            seed_sets = read_seed_sets(subject.seeds, subject.tensors)
        except ValueError as e:
            error = one_line(e)
        parts += list(seed_sets)
    request = {
        "subject": subject.id,
        "inputs": {role: _input_record(path, subject.cells[role]) for role, path in subject.inputs().items()},
        "tensor_order": subject.tensor_order, "tensor_frame": subject.tensor_frame,
        "work": {"connectivity": connectivity,
                 "seed_sets": {name: seeds if isinstance(seeds, dict) else [list(v) for v in seeds]
                               for name, seeds in seed_sets.items()}},
        "options": options, "report": report, "stvd": __version__}
    return _Plan(subject, folder, parts, seed_sets, request, error)


def _complete_statistics(plan):
    """The statistics of a subject complete from an earlier run of the same
    request, or None."""
    try:
        statistics = json.loads(read_regular_text(os.path.join(plan.folder, STATISTICS_FILE), RECORD_BYTES))
        if statistics.get("request") != plan.request:
            return None
        for name, record in statistics["outputs"].items():
            if os.path.getsize(os.path.join(plan.folder, name)) != record["bytes"]:
                return None
        if plan.report and not os.path.isfile(os.path.join(plan.folder, REPORT_FILE)):
            return None
        return statistics
    except (OSError, ValueError, KeyError, TypeError, AttributeError, RecursionError):
        return None


_SHA256 = re.compile(r"[0-9a-f]{64}")


def _is_output_name(name):
    """Whether ``name`` is a file name a subject's task writes (a plain name
    in the subject's folder)."""
    return (isinstance(name, str) and os.path.basename(name) == name and
            (name in (CONNECTIVITY_FILE, REPORT_FILE) or (name.startswith("distance_") and name.endswith(".nii.gz"))))


def _is_file_record(record):
    return (isinstance(record, dict) and isinstance(record.get("bytes"), int) and
            isinstance(record.get("sha256"), str) and _SHA256.fullmatch(record["sha256"]) is not None)


def _recorded_outputs(folder):
    """What earlier runs of ours recorded writing in a subject's folder,
    ``{file name: {'bytes', 'sha256'}}``: the outputs of its statistics.json
    and the QC page of its run.json (records that cannot be read, or
    entries that are not such records, count for nothing)."""
    recorded = {}
    for name in (STATISTICS_FILE, RUN_FILE):
        try:
            record = json.loads(read_regular_text(os.path.join(folder, name), RECORD_BYTES))
        except (OSError, ValueError, RecursionError):
            continue
        if not isinstance(record, dict):
            continue
        if name == STATISTICS_FILE:
            entries = record.get("outputs") if isinstance(record.get("outputs"), dict) else {}
        else:
            tasks = record.get("tasks") if isinstance(record.get("tasks"), list) else []
            entries = {REPORT_FILE: task["qc_page"] for task in tasks if isinstance(task, dict) and "qc_page" in task}
        recorded.update({file: entry for file, entry in entries.items()
                         if _is_output_name(file) and _is_file_record(entry)})
    return recorded


def _remove_if_ours(path, record, inputs):
    """Removes ``path`` when it is the file a run of ours recorded writing
    (a regular file of the recorded size and SHA-256) and no input of the
    run (``inputs``: (device, inode) of every input file); else nothing."""
    try:
        status = os.lstat(path)
    except OSError:
        return
    if (not stat.S_ISREG(status.st_mode) or status.st_size != record["bytes"] or
            (status.st_dev, status.st_ino) in inputs):
        return
    try:
        if file_record(path)["sha256"] == record["sha256"]:
            os.remove(path)
    except OSError:
        pass


def _summary_row(subject_id, statistics=None, error=None):
    row = dict.fromkeys(TABLE_COLUMNS, "")
    row["subject"] = subject_id
    if error is not None:
        row.update(status="failed", error=error)
        return row
    row["status"] = "ok"
    parts = statistics["parts"]
    if CONNECTIVITY in parts:
        c = parts[CONNECTIVITY]
        row.update(regions=len(c["regions"]), pairs_connected=c["pairs_connected"],
                   mean_geodesic_mm="" if c["mean_geodesic_mm"] is None else c["mean_geodesic_mm"])
    maps = [p for name, p in parts.items() if name != CONNECTIVITY]
    row["maps"] = len(maps)
    reached = [p["max_mm"] for p in maps if p["max_mm"] is not None]
    row["map_max_mm"] = max(reached) if reached else ""
    return row


def _start_subject(plan):
    """Prepares a subject's folder for computing: what earlier runs recorded
    writing there is noted (``plan.recorded``), then the records an earlier
    run left (its statistics first, so that the subject counts as incomplete
    until this run has finished it) are removed: they are outputs of this
    run, checked against every input."""
    os.makedirs(plan.folder, exist_ok=True)
    plan.recorded = _recorded_outputs(plan.folder)
    for name in (STATISTICS_FILE, RUN_FILE, ERROR_FILE):
        with contextlib.suppress(FileNotFoundError):
            os.remove(os.path.join(plan.folder, name))
    remove_leftover_staging_folders(plan.folder)


def _write_text(path, text):
    """One small output of the run (statistics, table), written whole or not
    at all."""
    with OutputFiles({os.path.basename(path): path}) as out:
        out.write_text(path, text)


def _finish_subject(plan, results, inputs=frozenset()):
    """Writes a computed subject's statistics (or its error) once all its
    parts are in; returns its row of the cohort table. ``inputs``: (device,
    inode) of every input file of the run, which is never removed."""
    errors = [r["error"] for r in results if "error" in r]
    if plan.error is not None:
        errors.insert(0, plan.error)
    parts, outputs = {}, {}
    for r in results:
        parts.update(r.get("parts", {}))
        outputs.update(r.get("outputs", {}))
    # The folder keeps the outputs of this request only: a failed subject
    # none (the parts that did finish are computed again with the others),
    # a complete one not those of an earlier request (a seed set renamed).
    # Only files a run of ours recorded writing are removed: this run's
    # results and the earlier runs' records, each still holding the bytes
    # recorded, and never an input.
    written = dict(plan.recorded)
    for r in results:
        written.update(r.get("outputs", {}))
        page = r.get("run", {}).get("qc_page")
        if page:
            written[REPORT_FILE] = page
    keep = set() if errors else set(outputs) | ({REPORT_FILE} if plan.report else set())
    for name, record in written.items():
        if name not in keep and _is_output_name(name) and _is_file_record(record):
            _remove_if_ours(os.path.join(plan.folder, name), record, inputs)
    if errors:
        _write_text(os.path.join(plan.folder, ERROR_FILE), errors[0] + "\n")
        return _summary_row(plan.subject.id, error=errors[0])
    statistics = {"request": plan.request,
                  "parts": {name: parts[name] for name in plan.parts},
                  "outputs": {name: outputs[name] for name in sorted(outputs)}}
    runs = [r["run"] for r in results]
    _write_text(os.path.join(plan.folder, RUN_FILE), json.dumps({
        "seconds": round(sum(r["seconds"] for r in runs), 3), "tasks": runs,
        "worker_peak_rss_mib": max(r["worker_peak_rss_mib"] for r in runs)}, indent=1) + "\n")
    _write_text(os.path.join(plan.folder, STATISTICS_FILE), json.dumps(statistics, indent=1) + "\n")
    return _summary_row(plan.subject.id, statistics)


def _table_text(rows):
    lines = ["\t".join(TABLE_COLUMNS)]
    lines += ["\t".join(str(row[c]).replace("\t", " ") for c in TABLE_COLUMNS) for row in rows]
    return "\n".join(lines) + "\n"


class _Progress:
    """A tqdm bar over the subjects, with done, failed and remaining."""

    def __init__(self, enabled, total, done):
        self._bar = None
        self.done, self.failed, self.total = done, 0, total
        if enabled:
            from tqdm.auto import tqdm

            self._bar = tqdm(total=total, initial=done, unit="subject", desc="cohort", file=sys.stderr)
            self._show()

    def _show(self):
        if self._bar is not None:
            self._bar.set_postfix_str(f"done {self.done}, failed {self.failed}, "
                                      f"remaining {self.total - self.done - self.failed}")

    def subject(self, row):
        if row["status"] == "ok":
            self.done += 1
        else:
            self.failed += 1
        self._show()
        if self._bar is not None:
            self._bar.update(1)

    def close(self):
        if self._bar is not None:
            self._bar.close()


LOOPBACK = "127.0.0.1"


@contextlib.contextmanager
def _dask_client(client, scheduler, workers, host):
    """The client to run on: the caller's, one connected to ``scheduler``,
    or one of an embedded LocalCluster of ``workers`` processes (one per
    core by default, one thread each), closed afterwards.

    The embedded cluster's scheduler, nannies, workers and their HTTP
    servers (the dashboard) listen on ``host`` only (this machine's
    loopback unless the caller names another), with a private scratch
    folder (not the shared ``dask-worker-space`` of the temporary folder).
    They talk TLS with keys made for this run only (``_security``): the
    loopback address is every local user's, and a Dask scheduler runs the
    work any client that connects submits.
    The processes it starts (workers, multiprocessing's resource tracker)
    start without the working folder on their module path: PYTHONSAFEPATH
    is set in this process's environment while the cluster runs (until
    they take their parent's module path, spawned interpreters would import
    from their working folder, which is this process's). When the run is
    interrupted (a termination signal, KeyboardInterrupt, any error) the
    workers are killed and waited for before the cluster is closed: none
    goes on with a subject and writes after the run has ended."""
    if client is not None:
        yield client
        return
    from distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            own = Client(scheduler, timeout="20s")
        except OSError as error:
            raise ConnectionError(f"cannot reach the Dask scheduler at {scheduler}: {one_line(error)}") from None
        with own:
            yield own
        return
    address = [(host, 0)]  # a pair, so that an IPv6 address needs no brackets
    security, protocol = _security()
    safe_path = os.environ.get("PYTHONSAFEPATH")
    os.environ["PYTHONSAFEPATH"] = "1"
    try:
        with _workers_do_not_import_main(), \
                tempfile.TemporaryDirectory(prefix="stvd-cohort-dask-") as scratch, \
                LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1, processes=True,
                             host=host, protocol=protocol, security=security, dashboard_address=address,
                             worker_dashboard_address=address, local_directory=scratch,
                             silence_logs=logging.ERROR) as cluster, \
                Client(cluster) as own:
            try:
                yield own
            except BaseException:
                _stop_workers_now(cluster)
                raise
    finally:
        if safe_path is None:
            os.environ.pop("PYTHONSAFEPATH", None)
        else:
            os.environ["PYTHONSAFEPATH"] = safe_path


@contextlib.contextmanager
def _workers_do_not_import_main():
    """While the embedded cluster runs, its worker processes start without
    importing the caller's main script again.

    Dask starts workers with multiprocessing's ``spawn``, which runs the
    main module of the parent again in each child (as ``__mp_main__``) when
    that module is a file (``python script.py``) or a module run with
    ``python -m``: it finds it by ``__main__.__file__`` and
    ``__main__.__spec__``. A script that calls ``stvd.cohort.run`` at its
    top level, without an ``if __name__ == "__main__":`` guard (the docs'
    snippet pasted into a file), would then start the cohort again in every
    worker. The workers run only stvd's own functions, which need nothing
    from the caller's script, so the two attributes are set aside while the
    cluster runs (spawned children then start as from an interactive
    session, which multiprocessing supports) and put back afterwards; no
    worker runs the script, guarded or not. (Other code of the caller's that
    spawns processes from another thread meanwhile would not get the script
    either; a cohort run blocks its own thread.)"""
    main = sys.modules.get("__main__")
    saved = {}
    if main is not None:
        for name in ("__file__", "__spec__"):
            if name in vars(main):
                saved[name] = vars(main)[name]
        main.__spec__ = None
        vars(main).pop("__file__", None)
    try:
        yield
    finally:
        if main is not None:
            for name in ("__file__", "__spec__"):
                if name in saved:
                    setattr(main, name, saved[name])
                else:
                    vars(main).pop(name, None)


def _in_a_spawned_childs_main_import():
    """Whether this process is a child of multiprocessing's ``spawn`` or
    ``forkserver`` that is importing its parent's main module (a worker of a
    cluster that was started without ``_workers_do_not_import_main``)."""
    import multiprocessing

    return bool(getattr(multiprocessing.current_process(), "_inheriting", False))


def _security():
    """Dask's security and protocol for the embedded cluster: mutual TLS
    with a certificate authority, key and certificate made for this run
    (in memory; the worker processes get them from their parent), so that
    only this run's client and workers can connect. Without the package
    cryptography (Debian: python3-cryptography), which makes them, plain TCP
    and a warning."""
    from distributed.security import Security

    try:
        return Security.temporary(), "tls://"
    except ImportError:
        print("stvd cohort: the package cryptography (python3-cryptography) is missing: the embedded cluster "
              "runs without TLS, and other users of this machine can submit work to it", file=sys.stderr)
        return None, "tcp://"


def _stop_workers_now(cluster):
    """Kills the worker processes of an embedded cluster (their nannies told
    not to start new ones) and waits until every one has ended."""
    import psutil

    processes = []
    for nanny in list(cluster.workers.values()):
        with contextlib.suppress(Exception):
            nanny.close_gracefully()  # no restart when its worker ends
        pid = getattr(nanny, "pid", None)
        if pid:
            with contextlib.suppress(psutil.Error):
                processes.append(psutil.Process(pid))
    for process in processes:
        with contextlib.suppress(psutil.Error):
            process.kill()
    for process in processes:
        # Ended (a zombie until its nanny reaps it) or gone.
        with contextlib.suppress(psutil.Error):
            while process.status() != psutil.STATUS_ZOMBIE:
                time.sleep(0.01)


def _dashboard(client):
    try:
        if "dashboard" in client.scheduler_info().get("services", {}):
            return client.dashboard_link
    except Exception:  # a link is a convenience, never a reason to fail
        pass
    return None


@contextlib.contextmanager
def _locked(outdir):
    """One run at a time per output folder (two would compute the same
    subjects and replace each other's outputs). The lock file is opened
    without following a link and without blocking, and must be a regular
    file: a link or a FIFO planted under its name is refused, never
    followed or waited on."""
    path = os.path.join(outdir, LOCK_FILE)
    try:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_NONBLOCK | os.O_CLOEXEC, 0o644)
    except OSError as error:
        if error.errno == errno.ELOOP:
            raise OSError(f"the lock file {LOCK_FILE} is a symbolic link, which stvd does not follow") from None
        raise OSError(f"cannot open the lock file {LOCK_FILE}: {error.strerror}") from None
    with os.fdopen(fd, "rb") as lock:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            raise OSError(f"the lock file {LOCK_FILE} is {kind_of(mode)}, not a regular file")
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            raise RuntimeError(f"{outdir}: another cohort run is writing into this folder") from None
        yield


def _check_files(manifest, outdir, plans, report):
    """No output of the run is an input of any subject, nor the manifest,
    nor another output: the library's check (``stvd.FileConflictError``)
    over the whole run, before any folder is made. Returns (device, inode)
    of every input file that exists (companions included): clean-up never
    removes one."""
    inputs = [("manifest", os.path.abspath(manifest))]
    for plan in plans:
        inputs += [(f"{column} input of subject {plan.subject.id}", path)
                   for column, path in plan.subject.inputs().items()]
    outputs = [(f"output {COHORT_TABLE}", os.path.join(outdir, COHORT_TABLE)),
               (f"lock file {LOCK_FILE}", os.path.join(outdir, LOCK_FILE))]
    if report:
        outputs.append((f"output {COHORT_INDEX}", os.path.join(outdir, COHORT_INDEX)))
    for plan in plans:
        outputs += [(f"output {name} of subject {plan.subject.id}", path)
                    for name, path in plan.output_files().items()]
    files = check_outputs_are_not_inputs(outputs, inputs)
    identities = set()
    for _, path in files.inputs:
        try:
            status = os.stat(path)
        except OSError:
            continue
        identities.add((status.st_dev, status.st_ino))
    return frozenset(identities)


def _check_path_lengths(manifest, plans):
    """ManifestError when a subject's files would have paths longer than
    the system takes (a long OUTDIR with long ids and seed set names):
    found before any work, not after other subjects' folders exist."""
    staging = ".stvd-staging-4194304-4294967295"  # the longest name of a staging folder
    for plan in plans:
        for path in plan.output_files().values():
            longest = os.path.join(os.path.dirname(path), staging, os.path.basename(path))
            length = len(longest.encode("utf-8", "surrogateescape"))
            if length > PATH_MAX:
                raise ManifestError(f"{manifest}, row {plan.subject.row}, column subject: in {os.path.dirname(path)} "
                                    f"the subject's files would have paths of {length} bytes, more than the "
                                    f"{PATH_MAX} the system takes")


def run(manifest, outdir, *, client=None, scheduler=None, workers=None, host=None, serial=False, connectivity=True,
        maps=True, split_seed_sets=False, threads=1, progress=False, report=True, method=None, k=None,
        chain_measure=None, stencil=None, max_distance=None, tensor_kind=None, diffusion_metric=None,
        max_anisotropy=None, fa_threshold=None, unreachable_value=None):
    """Runs every subject of ``manifest`` and writes into ``outdir``
    (created if needed). Returns a ``Cohort``.

    Where it runs: ``client=`` an existing ``distributed.Client``;
    ``scheduler=`` the address of a running Dask scheduler
    (``tcp://host:8786``); otherwise an embedded LocalCluster of
    ``workers`` processes (default: one per core), closed at the end, whose
    scheduler, workers and dashboard listen on ``host``: by default
    127.0.0.1, this machine only; name another address (``"0.0.0.0"``: all
    interfaces) to reach them from elsewhere, where anyone who can reach it
    sees the tasks (subject ids, paths, logs) and can submit work.
    ``serial=True`` runs the subjects one after the other in this process,
    without Dask (the reference for the cluster's outputs, which are the
    same bytes).

    The work: ``connectivity`` between the regions of each subject's labels,
    ``maps`` from each seed set of its seeds table (subjects without seeds
    get none). ``split_seed_sets=True`` makes a task of each part (the
    connectivity, each seed set) instead of one per subject.
    ``threads``: regions propagated at once within a connectivity task.
    ``report``: a QC page per subject (``stvd.report``: the connectivity and
    the first map, which ``split_seed_sets`` then computes in one task) and
    the cohort index ``OUTDIR/index.html``.

    Options as in ``stvd.distance`` (None: ``stvd.defaults``): ``method``,
    ``k``, ``chain_measure``, ``stencil``, ``max_distance`` (maps),
    ``tensor_kind``, ``diffusion_metric``, ``max_anisotropy``,
    ``fa_threshold``, ``unreachable_value`` (maps). The tensor order and
    frame and the mask come from the manifest.

    ``progress=True`` shows a tqdm bar of subjects done, failed and
    remaining. A manifest that cannot be run raises ``ManifestError``; an
    output that would be an input raises ValueError, before anything is
    written. Bad subjects do not raise: see ``Cohort.failed``.
    """
    if _in_a_spawned_childs_main_import():
        # A worker of someone else's cluster (or a multiprocessing pool)
        # importing the caller's script again: say so at once rather than
        # fail on the output folder's lock, restart, and fail again.
        raise RuntimeError(
            "stvd.cohort.run was called while a new worker process imported the main script again: the script "
            "calls it at its top level, and the process pool that started this worker runs the script in each of "
            "its processes. Put the call under `if __name__ == \"__main__\":`")
    start = time.perf_counter()
    options = dict(method=method, k=k, chain_measure=chain_measure, stencil=stencil, max_distance=max_distance,
                   tensor_kind=tensor_kind, diffusion_metric=diffusion_metric, max_anisotropy=max_anisotropy,
                   fa_threshold=fa_threshold, unreachable_value=unreachable_value)
    if not (connectivity or maps):
        raise ValueError("nothing to compute: neither connectivity nor maps")
    if host is not None and (serial or client is not None or scheduler is not None):
        raise ValueError("host= is where the embedded cluster listens: not with serial, client or scheduler")
    host = LOOPBACK if host is None else str(host)
    manifest = os.fspath(manifest)
    outdir = os.path.abspath(os.fspath(outdir))
    subjects = read_manifest(manifest)
    if not connectivity:
        for subject in subjects:
            if subject.seeds is None:
                raise ManifestError(f"{manifest}, row {subject.row}, column seeds: no seeds, and the run computes "
                                    "maps only (nothing to compute for this subject)")
    report = bool(report)
    plans = [_plan(subject, outdir, options, connectivity, maps, report) for subject in subjects]
    _check_path_lengths(manifest, plans)
    inputs = _check_files(manifest, outdir, plans, report)
    os.makedirs(outdir, exist_ok=True)

    with _locked(outdir):
        rows, pending = {}, []
        for plan in plans:
            statistics = _complete_statistics(plan)
            if statistics is not None:
                rows[plan.subject.id] = dict(_summary_row(plan.subject.id, statistics), computed=False)
            else:
                pending.append(plan)
        bar = _Progress(progress, len(plans), len(plans) - len(pending))
        dashboard, worker_count = None, 0
        try:
            for plan in pending:
                _start_subject(plan)
            if serial:
                for plan in pending:
                    results = [] if plan.error else [compute_parts(plan.subject, plan.parts, plan.seed_sets,
                                                                   plan.folder, _with_threads(options, threads),
                                                                   plan.report)]
                    rows[plan.subject.id] = dict(_finish_subject(plan, results, inputs), computed=True)
                    bar.subject(rows[plan.subject.id])
            elif pending:
                with _dask_client(client, scheduler, workers, host) as dask_client:
                    dashboard = _dashboard(dask_client)
                    if dashboard and progress:
                        print(f"stvd cohort: Dask dashboard at {dashboard}", file=sys.stderr)
                    worker_count = len(dask_client.scheduler_info().get("workers", {}))
                    _run_on_dask(dask_client, pending, _with_threads(options, threads), split_seed_sets, rows, bar,
                                 inputs)
        finally:
            bar.close()
            for plan in pending:  # what workers killed mid-write left behind
                if os.path.isdir(plan.folder):
                    remove_leftover_staging_folders(plan.folder)
        ordered = [rows[plan.subject.id] for plan in plans]
        table = os.path.join(outdir, COHORT_TABLE)
        _write_text(table, _table_text(ordered))
        index = _write_index(outdir, plans, ordered) if report else None
    return Cohort(ordered, table, time.perf_counter() - start, worker_count, dashboard, index)


def _write_index(outdir, plans, rows):
    """The cohort index page (``stvd.report.write_cohort_index``): every
    subject in the manifest's order, its QC page's summary, or its error."""
    from . import report

    pages = {os.path.dirname(os.path.abspath(entry["report"])): entry
             for entry in report.cohort_entries_from_folder(outdir) if entry.get("report")}
    entries = []
    for plan, row in zip(plans, rows):
        if row["status"] != "ok":
            entries.append({"subject": plan.subject.id, "status": "failed", "error": row["error"]})
        else:
            entries.append(pages.get(os.path.abspath(plan.folder),
                                     {"subject": plan.subject.id, "status": "missing", "error": "no QC page"}))
    path = os.path.join(outdir, COHORT_INDEX)
    report.write_cohort_index(path, entries, title=f"stvd cohort: {os.path.basename(outdir)}")
    return path


def _with_threads(options, threads):
    return dict(options, threads=threads)


def _run_on_dask(client, plans, options, split_seed_sets, rows, bar, inputs):
    """Submits the tasks (a subject, or with ``split_seed_sets`` a part of
    one), gathers the small results as they come, and finishes each subject
    when its last part is in. A task whose worker died is run again by the
    scheduler on another worker; one that keeps killing workers comes back
    as an error (KilledWorker) and fails its subject."""
    from distributed import as_completed

    futures, waiting, results = {}, {}, {}
    for order, plan in enumerate(plans):
        if plan.error is not None:
            rows[plan.subject.id] = dict(_finish_subject(plan, [], inputs), computed=True)
            bar.subject(rows[plan.subject.id])
            continue
        groups = [[part] for part in plan.parts] if split_seed_sets else [plan.parts]
        if plan.report and len(groups) > 1 and groups[0] == [CONNECTIVITY]:
            # The QC page shows the connectivity and the first map: one task.
            groups[:2] = [groups[0] + groups[1]]
        waiting[plan.subject.id] = len(groups)
        results[plan.subject.id] = []
        for group, parts in enumerate(groups):
            seed_sets = {name: plan.seed_sets[name] for name in parts if name != CONNECTIVITY}
            future = client.submit(compute_parts, plan.subject, parts, seed_sets, plan.folder, options,
                                   plan.report and group == 0, pure=False, priority=-order,
                                   key=f"stvd-cohort-{plan.subject.id}-{'+'.join(parts)}-{os.urandom(4).hex()}")
            futures[future] = plan
    for future in as_completed(list(futures)):
        plan = futures.pop(future)
        try:
            result = future.result()
        except Exception as error:  # the task could not run: its workers died, or the cluster went away
            result = {"error": f"the task failed on the cluster: {type(error).__name__}: {one_line(error)}"}
        future.release()
        subject = plan.subject.id
        results[subject].append(result)
        waiting[subject] -= 1
        if waiting[subject] == 0:
            rows[subject] = dict(_finish_subject(plan, results.pop(subject), inputs), computed=True)
            bar.subject(rows[subject])


# ---------------------------------------------------------------------------
# The command line: stvd cohort MANIFEST.tsv -o OUTDIR [options]

EXIT_OK, EXIT_INTERNAL, EXIT_USAGE, EXIT_SUBJECTS_FAILED, EXIT_OUTPUT = 0, 1, 2, 3, 5

DESCRIPTION = """\
Runs every subject of a manifest: the geodesic connectivity between the
regions of its label image (the table of `stvd connectivity`) and a distance
map from each seed set of its seeds table (the map of `stvd distance`), on an
embedded Dask cluster of one worker process per core, or on a running Dask
cluster (--scheduler). Writes OUTDIR/<subject>/ (connectivity.tsv,
distance_<set>.nii.gz, report.html, statistics.json, run.json; error.txt for
a subject that failed), OUTDIR/cohort.tsv and the cohort index
OUTDIR/index.html. A second run skips complete subjects and
computes the missing and failed ones. See docs/cohorts.md.

MANIFEST.tsv: a header row and one row per subject; columns subject, tensors,
labels (required), mask, tensor_order, tensor_frame, seeds (optional); paths
relative to the manifest's folder. Seeds: a TSV with columns name, i, j, k
(voxel indices from 0), rows with the same name forming one seed set; or a
label image on the tensors' grid, each non-zero value a seed set (label_<v>)."""

EPILOG = """\
Exit codes: 0 every subject complete; 1 internal error (or the cluster could
not be reached); 2 bad command line or manifest, or an output that is an
input (nothing written); 3 some subjects failed (their errors are in
cohort.tsv); 5 OUTDIR cannot be written."""


class _ArgumentParser(argparse.ArgumentParser):
    """Bad command lines as the tool reports them: one line, exit 2."""

    def error(self, message):
        print(f"stvd: {message} (see stvd cohort --help)", file=sys.stderr)
        sys.exit(EXIT_USAGE)


def _parser():
    parser = _ArgumentParser(prog="stvd cohort", description=DESCRIPTION, epilog=EPILOG,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("manifest", metavar="MANIFEST.tsv")
    parser.add_argument("-o", "--output", metavar="OUTDIR", required=True, help="the output folder")
    where = parser.add_argument_group("where it runs")
    where.add_argument("--scheduler", metavar="ADDRESS", help="a running Dask scheduler (tcp://host:8786)")
    where.add_argument("--workers", type=int, metavar="N",
                       help="worker processes of the embedded cluster (default: one per core)")
    where.add_argument("--host", metavar="ADDRESS",
                       help="where the embedded cluster's scheduler, workers and dashboard listen (default "
                       "127.0.0.1, this machine only; 0.0.0.0: every interface, where anyone who can reach "
                       "the machine sees the tasks and can submit work)")
    where.add_argument("--serial", action="store_true", help="one subject after the other in this process, no Dask")
    where.add_argument("--split-seed-sets", action="store_true",
                       help="a task per seed set and per connectivity table, not per subject (with QC pages "
                       "the table goes with the first seed set)")
    where.add_argument("--threads", type=int, default=1, metavar="N",
                       help="regions propagated at once within a connectivity task (default 1)")
    work = parser.add_argument_group("what it computes (options as in stvd distance; defaults: the tool's)")
    work.add_argument("--no-connectivity", action="store_true", help="distance maps only")
    work.add_argument("--no-maps", action="store_true", help="connectivity only")
    for option in OPTIONS:
        work.add_argument(option["flag"], dest=option["keyword"], metavar=option["value_name"],
                          type={"integer": int, "number": float}.get(option["type"], str),
                          help=option["help"]["cohort"].replace("\n", " ").replace("%", "%%"))
    shown = parser.add_argument_group("output")
    shown.add_argument("--progress", dest="progress", action="store_true", default=None,
                       help="a progress bar (default: when stderr is a terminal)")
    shown.add_argument("--no-progress", dest="progress", action="store_false")
    shown.add_argument("--report", dest="report", action="store_true", default=True,
                       help="a QC page per subject and the cohort index (the default)")
    shown.add_argument("--no-report", dest="report", action="store_false",
                       help="no QC pages (about 1-2 s less per subject)")
    shown.add_argument("-q", "--quiet", action="store_true", help="no summary on stdout")
    return parser


def main(argv=None):
    """``stvd cohort``: returns the exit code; errors are one line on stderr."""
    parser = _parser()
    args = parser.parse_args(argv)
    progress = sys.stderr.isatty() if args.progress is None else args.progress
    options = {name: getattr(args, name) for name in OPTION_NAMES}
    if args.threads < 1:
        parser.error("--threads must be at least 1")
    if args.workers is not None and args.workers < 1:
        parser.error("--workers must be at least 1")
    if args.serial and (args.scheduler or args.workers or args.host):
        parser.error("--serial runs in this process: no --scheduler, --workers or --host")
    if args.scheduler and args.host:
        parser.error("--host is where the embedded cluster listens: not with --scheduler")
    try:
        cohort = run(args.manifest, args.output, scheduler=args.scheduler, workers=args.workers, host=args.host,
                     serial=args.serial,
                     connectivity=not args.no_connectivity, maps=not args.no_maps,
                     split_seed_sets=args.split_seed_sets, threads=args.threads, progress=progress,
                     report=args.report, **options)
    except ValueError as error:  # the manifest, an output that is an input, options
        print(f"stvd: {one_line(error)}", file=sys.stderr)
        return EXIT_USAGE
    except (RuntimeError, ConnectionError) as error:  # the cluster, another run in OUTDIR
        print(f"stvd: {one_line(error)}", file=sys.stderr)
        return EXIT_INTERNAL
    except OSError as error:
        print(f"stvd: {args.output}: cannot write the outputs: {one_line(error)}", file=sys.stderr)
        return EXIT_OUTPUT
    failed = cohort.failed
    if not args.quiet:
        where = "serially" if cohort.workers == 0 else f"on {cohort.workers} Dask workers"
        print(f"Cohort of {len(cohort.subjects)} subjects: {len(cohort.computed)} computed {where}, "
              f"{len(cohort.subjects) - len(cohort.computed)} complete from an earlier run, {len(failed)} failed"
              + (f" ({', '.join(failed[:5])}{', ...' if len(failed) > 5 else ''})" if failed else "")
              + f". Took {cohort.seconds:.1f} s. Wrote {cohort.table}"
              + (f" and the index {cohort.index}." if cohort.index else "."))
    return EXIT_SUBJECTS_FAILED if failed else EXIT_OK


if __name__ == "__main__":
    from ._interruption import ending_by_signal

    with ending_by_signal():
        sys.exit(main())
