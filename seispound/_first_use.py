"""The first use of a compiled function: run its Python source while numba compiles it in the background.

numba compiles a kernel on its first call and caches the machine code (``cache=True``); on a fresh
install the integrator's drivers take 1-4 min to compile (``docs/performance.md``), while the
same loop run by the Python interpreter takes seconds on a bundled model: the loop is Python over
numpy arrays, which numba's ``NUMBA_DISABLE_JIT`` also runs, and its two forms agree to rounding
(``tests/test_first_use.py``, ``tests/integrate/test_driver.py``).

Inside :func:`interpret_first_use` (``simulate`` enters it), a call from Python of a package
function that has machine code neither in this process nor in numba's cache for its argument
types runs as Python, everything it calls included, and a process in the background
(``python -m seispound._compile_ahead``, at low priority) compiles it into the cache.  A timer
checks the Python run every :data:`TICK` s: once the machine code is in the cache, or once the
process has spent its budget of interpretation (:data:`INTERPRET_SECONDS`, environment
``SEISPOUND_INTERPRET_SECONDS``; 0 switches interpretation off), the run is stopped, its array
arguments are put back as they came, and it runs compiled (after waiting for the compile, in the
second case).  A first run therefore takes the shorter of its Python run and the compile, plus a
little, and a script of many runs switches to machine code as soon as there is some.

Outside that block, in threads other than the main one, or where ``SIGALRM`` is taken, a first call
compiles as numba does, and says so on stderr for a function given a :func:`label` (the
integrator's drivers).
"""

from __future__ import annotations

import contextlib
import os
import pickle
import signal
import subprocess
import sys
import threading
import time
from importlib import import_module
from pathlib import Path

import numpy as np

#: seconds of interpretation a process may spend before a first call waits for its compile instead
INTERPRET_SECONDS = 120.0
ONE_CORE_SECONDS = 15.0  # on one core the compile, at low priority, waits for the Python run: keep it short
TICK = 0.25  # s between the checks of a Python run: budget spent, or the machine code ready

depth = 0  # > 0 while a Python run goes on: every package function it calls runs as Python too
thread = None  # the thread (``threading.get_ident``) of that run: other threads keep their machine code
interpreted_calls = 0  # calls run as Python in this process (``integrate`` reads it into the run's stats)
_active = 0  # > 0 inside interpret_first_use()
_spent = 0.0  # seconds spent interpreting in this process
_pending: list = []  # (module, name, signature) queued for the background compile
_compiled_by: dict = {}  # (module, name, signature) -> the process compiling it
_labels: dict = {}  # id of a function -> (what it is, how long its compile takes), for the notices
_said: set = set()


class _OutOfTime(BaseException):
    """Raised in a Python run by its timer: the budget is spent or the machine code is ready (a BaseException, so
    that no ``except Exception`` of the package catches it)."""


def label(function, what: str, how_long: str) -> None:
    """Name ``function`` for the notices: ``what`` ("the fast integrator"), ``how_long`` its cold compile ("1-3 min")."""
    _labels[id(function)] = (what, how_long)


def budget() -> float:
    """Seconds of interpretation allowed per process: ``SEISPOUND_INTERPRET_SECONDS``, else :data:`INTERPRET_SECONDS`
    with two cores or more and :data:`ONE_CORE_SECONDS` with one (where the Python run and the compile share it)."""
    raw = os.environ.get("SEISPOUND_INTERPRET_SECONDS")
    try:
        return max(float(raw), 0.0) if raw is not None else INTERPRET_SECONDS if _cores() > 1 else ONE_CORE_SECONDS
    except ValueError:
        return INTERPRET_SECONDS


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


@contextlib.contextmanager
def interpret_first_use():
    """Within this block, a first call of an uncompiled package function from Python may run as Python."""
    global _active
    _active += 1
    try:
        yield
    finally:
        _active -= 1
        if not _active:
            _flush()


def first_call(function, args, kws, compiled):
    """Call ``function`` (a package dispatcher with no machine code in this process) on ``args``, ``kws``.

    ``compiled`` is numba's own call (it loads the cache or compiles).  Runs the Python source
    when :func:`interpret_first_use` is active, the function is not in numba's cache for these
    argument types, the budget is not spent and this is the main thread; otherwise compiles.
    """
    sig = _signature(function, args, kws)
    if sig is None or sig in function.overloads or _cached(function, sig):
        return compiled(*args, **kws)
    if not _may_interpret():
        return _machine_code(function, sig, args, kws, compiled)
    return _interpret(function, sig, args, kws, compiled)


def _machine_code(function, sig, args, kws, compiled, why=""):
    """``compiled(*args, **kws)`` after waiting for ``function``'s compile in the background if one runs (not the
    same compile twice); says what it does, each notice prefixed by ``why``."""
    job = _compiled_by.get(_key(function, sig))
    if job is not None and job.poll() is None:
        _say(function, why + "waiting for {what} to compile in the background ({how_long})", key="wait")
        job.wait()
    if job is None:
        _say(function, why + "compiling {what} (first use since installing; {how_long}, cached afterwards)")
    elif job.returncode:
        _say(function, _literal(f"the compile in the background failed (exit {job.returncode}; its messages: "
                                f"{job.log}): ") + "compiling {what} here ({how_long})", key="failed")
    return compiled(*args, **kws)


def _interpret(function, sig, args, kws, compiled):
    _queue(function, sig)
    if id(function) in _labels:  # a driver: its compile starts now; small helpers' at the block's end
        _flush()
    job = _compiled_by.get(_key(function, sig))
    _say(function, "{what} is not compiled yet (first use since installing): this run goes through its Python "
                   "source, the same code, while it compiles in the background for the next runs ({how_long})")
    saved = _copies((args, kws))
    done, out, failed = _python_run(function, args, kws, job)
    if done:
        return out
    _restore((args, kws), saved)  # the arguments as they came, for the compiled call
    if job is not None and job.poll() == 0:
        _say(function, "{what} has compiled in the background: this run goes on as machine code", key="ready")
        return compiled(*args, **kws)
    why = (_literal(f"its Python run stopped ({type(failed).__name__}: {failed}): ") if failed is not None
           else "the run is longer than interpreting pays for: ")
    _flush()  # the helpers queued before it, if the background compile has not started
    return _machine_code(function, sig, args, kws, compiled, why)


def _python_run(function, args, kws, job):
    """Run ``function``'s Python source under a timer that stops it (every :data:`TICK` s) once the budget is
    spent or ``job`` has compiled it: (True, its result, None), or (False, None, the error it raised or None)."""
    global depth, thread, interpreted_calls, _spent
    end = time.perf_counter() + budget() - _spent

    live = [True]  # off first thing in ``finally``: a tick that comes as the run ends must not raise there

    def tick(signum, frame):
        if live[0] and (time.perf_counter() >= end or (job is not None and job.poll() == 0)):
            raise _OutOfTime

    old = signal.signal(signal.SIGALRM, tick)
    start = time.perf_counter()
    thread = threading.get_ident()
    depth += 1
    try:
        signal.setitimer(signal.ITIMER_REAL, TICK, TICK)
        with np.errstate(all="ignore"):  # as machine code: no warnings of numpy's
            out = function.py_func(*args, **kws)
        interpreted_calls += 1
        return True, out, None
    except _OutOfTime:
        return False, None, None
    except Exception as err:  # Python's semantics (math.sqrt(-1) raises) are not numba's: the machine code decides
        return False, None, err
    finally:
        live[0] = False
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, old)
        depth -= 1
        _spent += time.perf_counter() - start


def _may_interpret() -> bool:
    return (_active > 0 and budget() > _spent and hasattr(signal, "setitimer")
            and threading.current_thread() is threading.main_thread()
            and signal.getsignal(signal.SIGALRM) in (signal.SIG_DFL, None))


def _signature(function, args, kws):
    """The argument types numba would compile ``function`` for (defaults folded in), or None if not typeable."""
    try:
        types_ = tuple(function.typeof_pyval(a) for a in args)
        kwtypes = {k: function.typeof_pyval(v) for k, v in kws.items()}
        return tuple(function.fold_argument_types(types_, kwtypes)[1])
    except Exception:  # numba types it or refuses it on its own call
        return None


def _cached(function, sig) -> bool:
    """True if numba's cache holds machine code of ``function`` for ``sig`` under the current sources, or if the
    function keeps no cache (nothing to gain from interpreting it once)."""
    cache = getattr(function, "_cache", None)
    try:
        key = cache._index_key(sig, function.targetctx.codegen())
        return key in cache._cache_file._load_index()
    except Exception:  # NullCache (cache=False) or a numba with another layout: behave as numba does
        return True


def _address(function):
    """(module, name) under which ``function`` is importable, or None."""
    module = getattr(function.py_func, "__module__", None)
    try:
        found = import_module(module)
    except Exception:
        return None
    for name, value in vars(found).items():
        if value is function:
            return module, name
    return None


def cache_dir(function) -> Path:
    """numba's cache directory for ``function`` (made if absent): the background compile's lock and log go there."""
    locator = function._cache._impl.locator
    locator.ensure_cache_path()
    return Path(locator.get_cache_path())


def _key(function, sig):
    """(module, name, signature) of ``function``: what the background compile is given, or None."""
    where = _address(function)
    return None if where is None else (*where, sig)


def _queue(function, sig) -> None:
    """Note ``function`` for the background compile (:func:`_flush`), once per function and signature."""
    key = _key(function, sig)
    if key is not None and key not in _compiled_by and key not in _pending:
        _pending.append(key)


def _flush():
    """Start one low-priority process compiling every queued function into numba's cache
    (``python -m seispound._compile_ahead``); returns it, or None if nothing was queued, it could not start, or
    ``SEISPOUND_COMPILE_AHEAD=0``."""
    jobs = list(_pending)
    _pending.clear()
    if not jobs or os.environ.get("SEISPOUND_COMPILE_AHEAD", "1") == "0":
        return None
    try:
        module, name, _ = jobs[-1]
        log = cache_dir(getattr(import_module(module), name)) / "seispound-compile.log"
        with open(log, "w") as err:
            proc = subprocess.Popen([sys.executable, "-m", "seispound._compile_ahead"], stdin=subprocess.PIPE,
                                    stdout=subprocess.DEVNULL, stderr=err, start_new_session=True)
        proc.log = str(log)
    except Exception:  # the run goes on as Python; the next one compiles
        return None
    try:
        proc.stdin.write(pickle.dumps(jobs))
        proc.stdin.close()
    except OSError:  # it ended before reading its work (a broken interpreter): its exit status and log say why
        with contextlib.suppress(OSError):
            proc.stdin.close()
    for job in jobs:
        _compiled_by[job] = proc
    return proc


def _arrays(value):
    """Every numpy array in ``value`` (nested tuples, lists and dicts), depth first."""
    if isinstance(value, np.ndarray):
        yield value
    elif isinstance(value, (tuple, list, dict)):
        for item in value.values() if isinstance(value, dict) else value:
            yield from _arrays(item)


def _copies(value) -> list:
    """Copies of every array in ``value``, in the order :func:`_restore` writes them back."""
    return [a.copy() for a in _arrays(value)]


def _restore(value, copies) -> None:
    """Write :func:`_copies`' arrays back into the arrays of ``value``, in place."""
    for a, saved in zip(_arrays(value), copies):
        if a.flags.writeable:
            a[...] = saved


def _literal(text: str) -> str:
    """``text`` as a part of a :func:`_say` template (its braces doubled)."""
    return text.replace("{", "{{").replace("}", "}}")


def _say(function, template: str, key: str = "") -> None:
    what = _labels.get(id(function))
    if what is None or (what[0], key, template) in _said:
        return
    _said.add((what[0], key, template))
    print("seispound: " + template.format(what=what[0], how_long=what[1]), file=sys.stderr, flush=True)
