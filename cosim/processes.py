"""Worker processes that do not outlive the command that started them.

``kill -9`` of a command gives it no chance to stop its workers: unless they notice on their own
they go on computing (and writing) for nobody, then idle forever. :func:`die_with_parent`, called
first thing in a worker process, makes it notice in two independent ways:

* on Linux, ``prctl(PR_SET_PDEATHSIG, SIGKILL)``: the kernel kills the worker the moment its
  parent dies, even while the worker is stuck in C code that holds the GIL. (The kernel sends it
  when the parent *thread* that started the worker ends; processes started from a thread that
  ends before them must pass ``pdeathsig=False``.)
* a watchdog thread that waits for the parent to end -- on a pidfd where the kernel has one
  (Linux >= 5.3: no polling, no confusion with a recycled pid), else by polling ``getppid``
  every ``poll`` seconds -- and then kills the worker. It works on every POSIX system, also
  when the parent is not the direct parent (a fork server), and whatever thread started it.

The parent pid is best passed from the parent (``os.getpid()`` there): a worker whose parent
died before it got here then exits at once (its watchdog finds the parent gone).

Examples
--------
A process pool whose workers die with the command:

>>> import os
>>> from concurrent.futures import ProcessPoolExecutor
>>> from cosim.processes import die_with_parent
>>> with ProcessPoolExecutor(2, initializer=die_with_parent, initargs=(os.getpid(),)) as pool:
...     list(pool.map(abs, [-1, -2]))
[1, 2]

A worker started with :mod:`subprocess` calls ``die_with_parent(PID)`` with the pid the parent
gave it (an argument or an environment variable), before its slow imports.
"""
from __future__ import annotations

import contextlib
import os
import select
import signal
import sys
import threading
from typing import Callable

__all__ = ["alive", "die_with_parent"]

PR_SET_PDEATHSIG = 1            # <linux/prctl.h>
_watching: set[tuple] = set()   # (this pid, parent pid) watched; a fork inherits the set, not the threads
_lock = threading.Lock()


def _die(signum: int) -> None:
    """End this process now: the signal (SIGKILL: no cleanup that could block), else _exit."""
    try:
        os.kill(os.getpid(), signum)
    finally:
        os._exit(128 + int(signum))


def _set_pdeathsig(signum: int) -> bool:
    """Linux: have the kernel send ``signum`` when the parent (thread) dies. False elsewhere."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(PR_SET_PDEATHSIG, int(signum), 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def alive(pid: int) -> bool:
    """Whether the process ``pid`` exists (also one of another user)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    return True


def _cleaning(cleanup: Callable[[], None], signum: int) -> Callable[[int], None]:
    """An end of the process that runs ``cleanup`` first (once, whoever calls it).

    A second signal that arrives while the cleanup runs re-enters the handler in the same
    thread: it returns at once, so that the cleanup below it goes on (waiting there would wait
    for itself)."""
    once = threading.Lock()
    cleaner: list[int] = []  # ident of the thread that runs the cleanup

    def end(received: int) -> None:
        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGTERM, signal.SIG_IGN)  # no second handler on top of this one
        if once.acquire(blocking=False):
            cleaner.append(threading.get_ident())
            try:
                cleanup()
            finally:
                os._exit(128 + int(received))
        if cleaner and cleaner[0] == threading.get_ident():
            return  # re-entered by a signal during our own cleanup
        threading.Event().wait()  # another thread is cleaning up and will exit

    return end


def _through_main_thread(end: Callable[[int], None], grace: float = 5.0) -> Callable[[int], None]:
    """The watchdog's end when a SIGTERM handler runs the cleanup: signal the main thread, so
    that the cleanup runs *there* and the main thread cannot go on starting new work (a new
    compiler) while the watchdog cleans up; after ``grace`` seconds (a main thread stuck in C)
    clean up from the watchdog."""

    def via_signal(received: int) -> None:
        os.kill(os.getpid(), signal.SIGTERM)
        threading.Event().wait(grace)
        end(received)

    return via_signal


def _watch(parent: int, direct: bool, poll: float, signum: int, end: Callable[[int], None] = _die) -> None:
    """Watchdog thread body: return only by ending this process once ``parent`` has ended."""
    fd = None
    if hasattr(os, "pidfd_open"):
        try:
            fd = os.pidfd_open(parent)
        except ProcessLookupError:
            end(signum)
        except OSError:  # kernel without pidfd (ENOSYS) or not permitted: poll instead
            fd = None
    if fd is not None and direct and os.getppid() != parent:
        end(signum)  # the pid was recycled before pidfd_open: we have been re-parented already
    if fd is not None:
        try:
            select.select([fd], [], [])  # readable when the process has ended
        finally:
            os.close(fd)
        end(signum)
    while True:
        if (direct and os.getppid() != parent) or not alive(parent):
            end(signum)
        threading.Event().wait(poll)


def die_with_parent(parent_pid: int | None = None, *, pdeathsig: bool = True, poll: float = 0.5,
                    signum: int = signal.SIGKILL, cleanup: Callable[[], None] | None = None) -> None:
    """Make the calling process end when its parent process ends (see the module docstring).

    Usable as a ``ProcessPoolExecutor``/``multiprocessing.Pool`` initializer. Calling it again
    for the same parent does nothing more.

    Parameters
    ----------
    parent_pid : int, optional
        Pid of the process to die with, as the parent saw itself (``os.getpid()`` there). Default:
        the current parent (``os.getppid()``), which cannot detect a parent that died before
        this call.
    pdeathsig : bool
        Also use Linux' ``PR_SET_PDEATHSIG`` (immediate; bound to the parent *thread*). Turn it
        off for processes started from a thread that ends before them.
    poll : float
        Seconds between checks of the watchdog where no pidfd is available.
    signum : int
        The signal that ends the process (default SIGKILL: nothing can block it).
    cleanup : callable, optional
        Called before the process ends because its parent ended (e.g. to stop child compilers and
        remove temporary files). With it the kernel sends SIGTERM instead of ``signum``, handled
        by ``cleanup`` then exit (the handler is installed when this is called from the main
        thread, as a pool initializer is); the watchdog calls it too.
    """
    ppid = os.getppid()
    parent = ppid if parent_pid is None else int(parent_pid)
    direct = parent == ppid
    watchdog_end = None
    if cleanup is not None:
        end = _cleaning(cleanup, signum)
        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGTERM, lambda *_: end(signal.SIGTERM))
            kernel_signal = signal.SIGTERM
            watchdog_end = _through_main_thread(end)
        else:
            kernel_signal = signum
    else:
        end, kernel_signal = _die, signum
    if pdeathsig and direct:
        _set_pdeathsig(kernel_signal)
        if os.getppid() != parent:  # died between getppid and prctl
            end(signum)
    with _lock:
        if (os.getpid(), parent) in _watching:
            return
        _watching.add((os.getpid(), parent))
    threading.Thread(target=_watch, args=(parent, direct, max(0.05, float(poll)), signum, watchdog_end or end),
                     name=f"die-with-{parent}", daemon=True).start()


def stop_pool(pool) -> None:
    """Cancel what has not started in ``pool`` (a ``concurrent.futures.ProcessPoolExecutor``) and
    stop its running workers: SIGTERM (they clean up), then SIGKILL after 5 s (a loaded machine).
    After it no worker runs, so none holds a lock or writes a file any longer."""
    processes = list((getattr(pool, "_processes", None) or {}).values())  # no public API before Python 3.14
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        with contextlib.suppress(Exception):
            process.terminate()
    for process in processes:
        process.join(timeout=5)
        if process.is_alive():
            process.kill()
            process.join()
