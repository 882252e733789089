"""Where independent tasks run: a Dask cluster, a local process pool or this process.

Monte Carlo batches, validity maps and sweep grid points are *tasks*: pure functions of
their arguments (random draws are seeded per draw, never per worker), so a task gives
the same bits wherever it runs. :func:`run_tasks` hands them to

* ``"dask"``: a ``dask.distributed`` cluster, either an existing one (``scheduler =
  "tcp://HOST:8786"``) or a local cluster of this machine's cores started for the call
  (one single-threaded worker process per core, listening on 127.0.0.1 only). A worker
  that dies takes its running tasks with it; the scheduler gives them to another worker;
* ``"pool"``: a :class:`concurrent.futures.ProcessPoolExecutor` on this machine (what runs
  when Dask is not installed);
* ``"serial"``: this process, one task after the other;

and calls ``on_result(index, result)`` in the calling process as each task finishes (in
completion order), which is where results are streamed to a store.

A task that raises one of the tool's own errors (:class:`~ins_errors.errors.InsErrorsError`:
bad input found by that task, such as a motion that reaches a pole) stops the whole call
with that error, unless the caller passes ``on_failure``: then the error is that task's
outcome, ``on_failure(index, error)`` is called for it and the other tasks run on. Any
other exception (a fault, a worker that cannot be reached) and Ctrl-C stop the call
either way. So does SIGTERM (a batch system's time limit): it raises :class:`Terminated`
(a :class:`KeyboardInterrupt`) in the calling process, which stops the workers (a process
pool's at once, abandoning their running tasks) and keeps what was reported, as Ctrl-C
does; a pool worker also ends when the calling process dies (Linux).

Dask is the optional extra ``ins-errors[distributed]``; :data:`INSTALL_HINT` says how to
install it.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
import time
import weakref
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from typing import Any

from ins_errors.errors import InsErrorsError, unknown_name

ENGINES = ("auto", "dask", "pool", "serial")
"""Engine names :func:`run_tasks` accepts (``"auto"``: Dask if installed, else the pool)."""

SMALL_RUN_PER_WORKER = 2
"""``"auto"`` runs at most this many tasks per worker on the process pool even where Dask
is installed: a local Dask cluster takes seconds to start (4-5 s wall on two cores), more
than such a run saves by it (a 4-point sweep: 8-12 s on Dask, 7 s in one process)."""

INSTALL_HINT = "pip install 'ins-errors[distributed]'"
"""How to install the Dask engine."""


class EngineError(InsErrorsError):
    """Tasks that cannot be run: no Dask, an unreachable scheduler, a task lost for good."""


class Terminated(KeyboardInterrupt):
    """``SIGTERM`` (a batch system's time limit, ``kill``) received while tasks ran.

    Raised in the calling process as Ctrl-C raises :class:`KeyboardInterrupt` (it is
    one), so that the same clean-up runs: the workers are stopped, the results reported
    so far are kept (a sweep's store stays resumable). The command line exits with
    128 + :attr:`signum` (143).
    """

    signum = int(signal.SIGTERM)


@dataclass
class EngineStats:
    """What a :func:`run_tasks` call did.

    Attributes
    ----------
    engine : str
        ``"dask"``, ``"pool"`` or ``"serial"``.
    workers : int
        Workers the tasks were spread over (1 for serial).
    computed : int
        Tasks that ran to completion and were reported.
    where : str
        Human description (scheduler address, pool size).
    failed : int
        Tasks whose error was reported to ``on_failure`` (see :func:`run_tasks`).
    """

    engine: str
    workers: int
    computed: int = 0
    where: str = ""
    failed: int = 0


def dask_available() -> bool:
    """True when ``dask.distributed`` can be imported."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        return False
    return True


_SAID = {"no dask": False}
"""What this process has told the user already."""


def choose_engine(engine: str = "auto", scheduler: str | None = None) -> str:
    """Resolve ``"auto"`` and check that the chosen engine can run here.

    Raises
    ------
    EngineError
        A scheduler address or ``"dask"`` without Dask installed, or a scheduler address
        together with a non-Dask engine.
    """
    if engine not in ENGINES:
        raise unknown_name("engine", engine, ENGINES)
    if scheduler is not None:
        if engine not in ("auto", "dask"):
            raise EngineError(f"a scheduler address ({scheduler}) needs the dask engine, "
                              f"not {engine!r}")
        engine = "dask"
    if engine == "dask" and not dask_available():
        raise EngineError(f"the dask engine needs Dask: {INSTALL_HINT}")
    if engine == "auto":
        if dask_available():
            return "dask"
        if not _SAID["no dask"]:  # (a command may resolve its engine more than once)
            print(f"ins-errors: Dask is not installed, running on a local process pool "
                  f"(for Dask and clusters: {INSTALL_HINT})", file=sys.stderr)
            _SAID["no dask"] = True
        return "pool"
    return engine


def run_tasks(function: Callable[..., Any], tasks: Sequence[tuple], *,
              engine: str = "auto", scheduler: str | None = None,
              workers: int | None = None, shared: tuple = (),
              on_result: Callable[[int, Any], None] | None = None,
              on_failure: Callable[[int, InsErrorsError], None] | None = None,
              progress: bool = False, label: str = "tasks") -> EngineStats:
    """Run ``function(*shared, *task)`` for every task and report results as they finish.

    Parameters
    ----------
    function : callable
        A module-level function (workers import it by name).
    tasks : sequence of tuple
        Arguments of each task; task ``k`` is reported as index ``k``.
    engine : {"auto", "dask", "pool", "serial"}
        ``"auto"``: :func:`choose_engine`'s choice, except that a local run of at most
        :data:`SMALL_RUN_PER_WORKER` tasks per worker takes the process pool.
    scheduler : str, optional
        Address of a running Dask scheduler, e.g. ``"tcp://10.0.0.5:8786"``; default: a
        local cluster started (and shut down) by this call.
    workers : int, optional
        Workers of a local cluster or pool (default: this machine's cores).
    shared : tuple
        Leading arguments common to every task (sent to each Dask worker once).
    on_result : callable, optional
        ``on_result(k, result)``, called in this process as each task finishes.
    on_failure : callable, optional
        ``on_failure(k, error)``, called in this process for a task that raised an
        :class:`~ins_errors.errors.InsErrorsError` (its own bad input); the other tasks
        run on. Default: such an error stops the call and is raised.
    progress : bool
        Show a progress bar over tasks.
    label : str
        Name of the tasks in the progress bar.

    Returns
    -------
    EngineStats

    Raises
    ------
    EngineError
        See :func:`choose_engine`; also when the scheduler cannot be reached, a task
        killed its workers repeatedly or a task failed with another exception.
    InsErrorsError
        The error of a task, when ``on_failure`` is not given.
    """
    asked = engine
    engine = choose_engine(engine, scheduler)
    cores = os.cpu_count() or 1
    workers = max(1, workers or cores)
    if asked == "auto" and scheduler is None and engine == "dask" and (
            len(tasks) <= SMALL_RUN_PER_WORKER * workers):
        engine = "pool"  # a few tasks: no local cluster to start
    report = on_result or (lambda k, r: None)
    bar = None
    from ins_errors.progress import on_terminal

    if progress and tasks and on_terminal():
        from tqdm import tqdm

        # None: no bar when stderr is not a terminal; every task drawn as it is done (a
        # few tasks of seconds each: the bar never lags the count a stop reports)
        bar = tqdm(total=len(tasks), unit="task", desc=label, leave=False,
                   disable=None, miniters=1, mininterval=0)

    def done(k: int, result: Any) -> None:
        check_terminated()
        report(k, result)
        stats.computed += 1
        if bar is not None:
            bar.update(1)

    def failed(k: int, error: BaseException) -> None:
        """A task raised ``error``: its outcome (``on_failure``) or the end of the call."""
        check_terminated()
        if on_failure is None or not isinstance(error, InsErrorsError) or isinstance(
                error, EngineError):
            raise task_failure(error, label) from None
        on_failure(k, error)
        stats.failed += 1
        if bar is not None:
            bar.update(1)

    from ins_errors.numeric.integrators import compiler_checked

    with terminate_interrupts():  # SIGTERM: the clean-up of Ctrl-C, then exit 143
        try:
            if engine == "serial" or not tasks:
                stats = EngineStats("serial", 1, where="this process")
                for k, task in enumerate(tasks):
                    try:
                        result = function(*shared, *task)
                    except InsErrorsError as error:
                        failed(k, error)
                        continue
                    done(k, result)
            elif engine == "pool":
                count = min(workers, len(tasks))
                stats = EngineStats("pool", count, where=f"local process pool of {count}")
                with compiler_checked():  # no compiler: said once, not by each worker
                    _run_pool(function, tasks, shared, stats.workers, done, failed)
            else:
                stats = EngineStats("dask", 0)
                with compiler_checked():
                    _run_dask(function, tasks, shared, scheduler,
                              min(workers, len(tasks)), stats, done, failed, label)
        finally:
            if bar is not None:
                bar.close()
    return stats


def task_failure(error: Exception, label: str) -> InsErrorsError:
    """The one-line error of a task that failed in a worker process.

    An error of the tool's own (:class:`~ins_errors.errors.InsErrorsError`: bad input
    found by the task) is passed on as it is; any other exception (a task that cannot be
    sent to the worker, a worker that died, a fault) becomes an :class:`EngineError`
    naming its type and first line, so that the command line reports it like any other
    error (exit status 2, one line) and never as a traceback from another process.
    """
    if isinstance(error, InsErrorsError):
        return error
    text = str(error).strip().splitlines()
    return EngineError(f"a {label} task failed in a worker process: "
                       f"{type(error).__name__}{': ' + text[0] if text else ''}")


def _run_pool(function, tasks, shared, workers, done, failed) -> None:
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor, as_completed

    # fork: no re-import of the caller's __main__, loaded models and compiled code shared
    methods = multiprocessing.get_all_start_methods()
    context = multiprocessing.get_context("fork" if "fork" in methods else "spawn")
    with ProcessPoolExecutor(workers, mp_context=context, initializer=_pool_worker_starts,
                             initargs=(os.getpid(),)) as pool:
        futures = {}
        try:
            for k, task in enumerate(tasks):
                futures[pool.submit(function, *shared, *task)] = k
            check_terminated()  # (a SIGTERM while the workers were forked)
            for future in as_completed(futures):
                try:
                    result = future.result()
                except Exception as error:  # the task's outcome, or any fault in one line
                    failed(futures[future], error)
                    continue
                done(futures[future], result)
        except BaseException as error:
            for future in futures:
                future.cancel()
            if isinstance(error, KeyboardInterrupt):  # Ctrl-C, SIGTERM: not their ends
                _stop_workers(pool)
            raise


WORKER_GRACE = 5.0
"""Seconds a stopped pool worker has to end on SIGTERM before it is killed."""


def _pool_worker_starts(parent: int) -> None:
    """Run in each pool worker as it starts (``parent``: the process id of the pool's
    owner). Ctrl-C is left to the owner, which stops the workers itself (their
    KeyboardInterrupt tracebacks buried its one line); SIGTERM ends the worker (not the
    owner's handler, inherited through ``fork``, which would make it a task's error);
    on Linux the owner's end, even by SIGKILL (a batch system's last word after its
    SIGTERM), ends the worker too: no worker is left orphaned, waiting forever."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if sys.platform.startswith("linux"):
        try:
            import ctypes

            set_parent_death_signal = 1  # PR_SET_PDEATHSIG of prctl(2)
            ctypes.CDLL(None).prctl(set_parent_death_signal, int(signal.SIGTERM), 0, 0, 0)
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:  # the owner ended before the above
        os._exit(1)


def _stop_workers(pool) -> None:
    """End a process pool's workers now, their running tasks abandoned: no new task is
    started, each worker gets SIGTERM, and SIGKILL after :data:`WORKER_GRACE` s."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    results = getattr(pool, "_result_queue", None)
    manager = getattr(pool, "_executor_manager_thread", None)
    if manager is not None:
        _STOPPED_MANAGERS.add(manager)
    threading.excepthook = _quiet_stopped_pool(threading.excepthook)
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join(WORKER_GRACE)
        if process.is_alive():
            process.kill()
            process.join(WORKER_GRACE)
    # a worker ended while it sent a result leaves half a message in the result pipe,
    # whose reader (the pool's manager thread, joined as the interpreter exits) then
    # waits for the rest forever: the process printed its line and never ended. The
    # workers are gone; this end of the pipe closed, the reader sees its end.
    writer = getattr(results, "_writer", None)
    if writer is not None:
        with suppress(OSError):
            writer.close()


_STOPPED_MANAGERS: weakref.WeakSet = weakref.WeakSet()
"""The manager threads of the process pools :func:`_stop_workers` stopped."""


def _quiet_stopped_pool(hook: Callable) -> Callable:
    """``threading.excepthook`` that passes over the one error of a stopped pool's manager
    thread (one in :data:`_STOPPED_MANAGERS`) that the stop causes, and hands every other
    to ``hook`` (another pool's, e.g. a notebook user's own, is shown as before).

    Python 3.11's manager thread, finding the workers ended, marks each pending task
    failed, including those the stop has just cancelled; that raises
    ``InvalidStateError`` in the thread, whose traceback was printed between the sweep's
    notes and its one line (about one stop in ten under load). The tasks are abandoned
    on purpose; nothing is lost.
    """
    from concurrent.futures import InvalidStateError

    if getattr(hook, "quiet_stopped_pool", False):
        return hook

    def quiet(args: threading.ExceptHookArgs) -> None:
        if isinstance(args.exc_value, InvalidStateError) and args.thread in _STOPPED_MANAGERS:
            return
        hook(args)

    quiet.quiet_stopped_pool = True  # type: ignore[attr-defined]
    return quiet


REPEAT_WINDOW = 1.0
"""Seconds after a first SIGTERM within which another is taken as the same stop."""


@contextmanager
def terminate_interrupts(lasting: bool = False) -> Iterator[None]:
    """While tasks run (and, from the command line, while any command runs: ``cli.main``),
    SIGTERM raises :class:`Terminated` in this process instead of ending it at once: its
    default action left a process pool's workers running, orphaned, and skipped the
    clean-up Ctrl-C gets (a store's lock, a scratch folder, the one line saying why).
    Only in the main thread (the only one that may set handlers) and where SIGTERM has
    its default action (a handler the program set is kept); a second SIGTERM during the
    clean-up ends the process, unless it comes within :data:`REPEAT_WINDOW` of the first
    (the same stop sent twice: ``timeout`` signals the process, then its group).

    A :class:`Terminated` that Python drops (raised while a finaliser or an at-fork hook
    runs, where exceptions are printed as "Exception ignored" and lost) is not printed
    but raised again by :func:`check_terminated`, which :func:`run_tasks` calls as tasks
    start and finish, and at the end of the block.

    Parameters
    ----------
    lasting : bool
        Once SIGTERM came, ignore it after the block (the command line: the process is
        ending, and a repeat of the same stop during its exit, which resets Python's
        handlers, would end it in silence with the default action; SIGKILL still ends
        it).
    """
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGTERM) is not signal.SIG_DFL):
        yield
        return
    owner = os.getpid()

    def stop(signum, frame) -> None:
        if os.getpid() != owner:  # a pool worker forked before it set its own
            signal.signal(signal.SIGTERM, signal.SIG_DFL)
            os.kill(os.getpid(), signal.SIGTERM)
            return
        if not _TERMINATED:
            _TERMINATED.append(time.monotonic())
            raise Terminated
        if time.monotonic() - _TERMINATED[0] < REPEAT_WINDOW:
            return  # the same stop twice (`timeout` signals the process and its group)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)
        os.kill(os.getpid(), signal.SIGTERM)

    shown = sys.unraisablehook

    def dropped(unraisable) -> None:
        if unraisable.exc_type is not None and issubclass(unraisable.exc_type, Terminated):
            _DROPPED.append(True)  # raised again by check_terminated
            return
        if _TERMINATED:  # the stop under way broke it (see below): not the user's news
            return
        shown(unraisable)

    _TERMINATED.clear()
    _DROPPED.clear()
    signal.signal(signal.SIGTERM, stop)
    sys.unraisablehook = dropped
    try:
        yield
        check_terminated()
    finally:
        sys.unraisablehook = shown
        _DROPPED.clear()
        # the command line, once stopped, is ending: a repeat of the stop is ignored
        # (Python's exit would give it the default action, ending it in silence)
        signal.signal(signal.SIGTERM, signal.SIG_IGN if lasting and _TERMINATED
                      else signal.SIG_DFL)
        _TERMINATED.clear()


_TERMINATED: list[float] = []
"""When :func:`terminate_interrupts`' handler got SIGTERM (empty: it did not). Once it
has, errors Python can only print ("Exception ignored in ...") are not printed: the stop
raised into code that cannot take it (a SIGTERM inside ``os.fork``'s callbacks left
logging's lock half-taken, and its release after the fork printed a RuntimeError and a
traceback before the one line; seen once under load), and the command is ending."""

_DROPPED: list[bool] = []
"""Non-empty when Python dropped the handler's :class:`Terminated`."""


def check_terminated() -> None:
    """Raise :class:`Terminated` again if Python dropped the one SIGTERM raised.

    Python runs a signal's handler wherever the main thread is; an exception raised
    there inside a finaliser or an at-fork hook (a process pool starting its workers) is
    handed to :data:`sys.unraisablehook` and dropped (the sweep then ran on to its end).

    Raises
    ------
    Terminated
    """
    if _DROPPED:
        _DROPPED.clear()
        raise Terminated


@contextmanager
def _workers_ignore_ctrl_c() -> Iterator[None]:
    """Start a local cluster's processes deaf to Ctrl-C, yet stop after the start if
    Ctrl-C came during it.

    Ctrl-C in the terminal reaches the whole process group, and the workers' own
    KeyboardInterrupt tracebacks (and a compile killed mid-way, which looked like a
    broken compiler) buried the one line the sweep prints; the sweep's own process stops
    and closes the cluster, which ends the workers. So SIGINT is *blocked* in this thread
    while the cluster starts: the threads that start the worker processes (created
    meanwhile) inherit the block, and so do the processes and the compilers they run
    (SIGINT stays pending in them, never delivered). A Ctrl-C meanwhile goes to a
    handler of this process that only notes it (it never stops the start half-way,
    leaving threads and processes behind); once the start returns, the signal is raised
    again with the previous handler back: KeyboardInterrupt, and the caller closes the
    cluster just started. (The block used to set SIGINT ignored, which the workers
    inherited too, but a Ctrl-C in the seconds of the start was then lost: the sweep ran
    on to its end.)

    Where SIGINT is ignored already (a job started in the background), off the main
    thread (only it may set handlers), or without ``pthread_sigmask``, nothing changes.
    """
    if (threading.current_thread() is not threading.main_thread()
            or not hasattr(signal, "pthread_sigmask")):
        yield
        return
    previous = signal.getsignal(signal.SIGINT)
    if previous is signal.SIG_IGN or previous is None:  # ignored (inherited), or not
        yield                                           # Python's: left as it is
        return
    # multiprocessing's resource tracker, started by the first process a thread starts,
    # unblocks SIGINT in that thread (it had blocked it for the tracker's own start):
    # started here first, before the block, it leaves the threads of the start blocked
    from multiprocessing import resource_tracker

    resource_tracker.ensure_running()
    came: list[int] = []
    signal.signal(signal.SIGINT, lambda signum, frame: came.append(signum))
    mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        # a Ctrl-C held by the block is delivered here, to the handler that notes it
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        signal.signal(signal.SIGINT, previous)
    if came:
        signal.raise_signal(signal.SIGINT)  # the previous handler: KeyboardInterrupt


CUT_SHORT_CLOSE_TIMEOUT = 10.0
"""Seconds a local cluster whose start was cut short has to close (:func:`_closed_if_cut_short`)."""


@contextmanager
def _closed_if_cut_short() -> Iterator[None]:
    """Close the local Dask cluster whose start a stop cuts short, quietly.

    SIGTERM raises :class:`Terminated` wherever the main thread is, also inside
    ``LocalCluster(...)`` while the cluster starts (its workers starting in a thread of
    their own): no cluster object reaches the caller, and Dask's own ``close_clusters``,
    run as the interpreter exits, closed it then, with workers still starting, and
    printed "Exception ignored in atexit callback" and an ``AssertionError:
    Status.init`` traceback after the command's one line. Here the cluster made by the
    block (Dask keeps every one it makes in ``SpecCluster._instances``) is closed at
    once, what that close breaks on its way is not printed (the command is stopping:
    neither its errors nor those its event loop would log, such as the start of a worker
    process the same SIGTERM ended), and it is taken off Dask's list, so its exit does
    not close it again.
    """
    from distributed.deploy.spec import SpecCluster

    before = set(SpecCluster._instances)
    try:
        yield
    except BaseException:
        for cluster in set(SpecCluster._instances) - before:
            SpecCluster._instances.discard(cluster)
            # its event loop's tasks failed by the stop (workers the same SIGTERM ended
            # mid-start) are logged "Task exception was never retrieved" when collected
            loop = getattr(getattr(cluster, "loop", None), "asyncio_loop", None)
            if loop is not None:
                loop.set_exception_handler(lambda loop, context: None)
            with suppress(BaseException):  # a start cut short: whatever it left
                cluster.close(timeout=CUT_SHORT_CLOSE_TIMEOUT)
        raise


def _run_dask(function, tasks, shared, scheduler, workers, stats, done, failed,
              label: str = "tasks") -> None:
    import logging

    from distributed import Client, LocalCluster, as_completed
    from distributed.scheduler import KilledWorker

    cluster = None
    try:
        if scheduler is None:
            with _workers_ignore_ctrl_c(), _closed_if_cut_short():
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1,
                                       processes=True, host="127.0.0.1",
                                       dashboard_address="127.0.0.1:0",
                                       silence_logs=logging.CRITICAL)
            client = Client(cluster)
            stats.where = f"local Dask cluster of {workers} worker(s)"
        else:
            try:
                client = Client(scheduler, timeout="10s")
            except (OSError, TimeoutError, ValueError) as error:
                raise EngineError(f"cannot reach the Dask scheduler at {scheduler}: "
                                  f"{str(error).splitlines()[0] if str(error) else error!r}"
                                  ) from None
            stats.where = f"Dask scheduler {scheduler}"
        try:
            stats.workers = len(client.scheduler_info().get("workers", {}))
            try:
                common = [client.scatter(item, broadcast=True) for item in shared]
                futures = [client.submit(function, *common, *task, pure=False)
                           for task in tasks]
            except Exception as error:  # e.g. not serialisable
                raise task_failure(error, label) from None
            index = {future.key: k for k, future in enumerate(futures)}
            try:
                for future in as_completed(futures):
                    try:
                        result = future.result()
                    except KilledWorker as error:
                        raise EngineError(f"a task kept killing its Dask workers: {error}"
                                          ) from None
                    except Exception as error:  # the task's outcome, or any fault
                        failed(index[future.key], error)
                    else:
                        done(index[future.key], result)
                    future.release()
            except BaseException:
                client.cancel(futures)
                raise
        finally:
            client.close()
    finally:
        if cluster is not None:
            cluster.close()
