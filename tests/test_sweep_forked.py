"""Chunks on forked processes (:mod:`railcheck.parallel.forked`; results in the items' order:
``tests/test_sweep_threads.py``, for both): at most ``ahead`` started beyond the awaited
one, an error at its turn (picklable or not), a child that dies is a one-line error, and
no child outlives a stopped call."""

import multiprocessing
import os
import signal
import time

import pytest

from railcheck.base.errors import InputError, RailcheckError
from railcheck.parallel import forked
from railcheck.parallel.forked import in_order_on_processes

# slow tier (one pytest process): the tests fork and terminate children
pytestmark = [pytest.mark.skipif(not forked.available(), reason="forks only on Linux"), pytest.mark.slow]


def test_the_function_and_items_reach_the_children_without_pickling():
    unpicklable = lambda i: (i, os.getpid())  # noqa: E731  # a lambda cannot be pickled
    got = list(in_order_on_processes(unpicklable, list(range(8)), 2, ahead=2))
    assert [i for i, _ in got] == list(range(8))
    assert os.getpid() not in {pid for _, pid in got}  # computed in the children


def test_no_more_than_ahead_items_are_started_beyond_the_awaited_one():
    taken = multiprocessing.Value("i", 0)  # shared memory: the children see the caller's count
    worst = multiprocessing.Value("i", 0)

    def record(i):
        with worst.get_lock():
            worst.value = max(worst.value, i - taken.value)
        time.sleep(0.001)
        return i

    for value in in_order_on_processes(record, list(range(30)), processes=3, ahead=2):
        time.sleep(0.005)  # a slow consumer: the workers would run ahead if allowed
        taken.value = value + 1
    assert 1 <= worst.value <= 2 + 1  # the awaited item itself, plus two ahead


def test_an_error_is_raised_at_its_turn_after_the_results_before_it():
    def fail_at_5(i):
        if i == 5:
            raise InputError("mechanism.crank", "item 5")
        return i

    got = []
    with pytest.raises(InputError, match="item 5") as caught:
        for value in in_order_on_processes(fail_at_5, list(range(20)), processes=2, ahead=3):
            got.append(value)
    assert got == [0, 1, 2, 3, 4]
    assert caught.value.field == "mechanism.crank"  # the error whole, not its text


def test_an_error_that_cannot_be_pickled_comes_back_named():
    class Local(Exception):  # a local class cannot be pickled
        pass

    def fail(i):
        raise Local("not picklable")

    with pytest.raises(RuntimeError, match="Local: not picklable"):
        list(in_order_on_processes(fail, [0, 1], processes=2, ahead=1))


def _recorder(slots: int):
    """A shared array the children write their pids into (the test's own children, named
    exactly: other tests' processes in this test process do not count)."""
    pids = multiprocessing.Array("i", slots)
    return pids, lambda: {p for p in pids[:] if p}


def test_a_child_that_dies_is_a_one_line_error_and_no_child_is_left():
    pids, ours = _recorder(10)

    def die_at_3(i):
        pids[i] = os.getpid()
        if i == 3:
            os.kill(os.getpid(), signal.SIGKILL)  # the OOM killer, say
        time.sleep(0.01)
        return i

    with pytest.raises(RailcheckError, match="worker process died"):
        list(in_order_on_processes(die_at_3, list(range(10)), processes=2, ahead=2))
    assert 1 <= len(ours()) <= 2  # the pool's two children (a broken pool starts no other)
    assert not [pid for pid in ours() if _alive(pid)]


def test_a_child_that_dies_while_the_caller_writes_is_the_same_one_line_error():
    """The death seen when the caller next submits (it was busy with a result): the same
    error, not the pool's own."""

    def die_at_1(i):
        if i == 1:
            time.sleep(0.2)  # after item 0's result is taken
            os.kill(os.getpid(), signal.SIGKILL)
        return i

    with pytest.raises(RailcheckError, match="worker process died"):
        for _ in in_order_on_processes(die_at_1, list(range(10)), processes=2, ahead=1):
            time.sleep(0.5)  # writing the result: the pool breaks meanwhile


def test_the_children_are_stopped_at_once_when_the_caller_stops(tmp_path):
    """Run in a fresh interpreter, as `railcheck sweep` runs it."""
    import json
    import subprocess
    import sys

    script = tmp_path / "caller.py"
    script.write_text(
        "import json, multiprocessing, os, time\n"
        "from railcheck.parallel.forked import in_order_on_processes\n"
        "pids = multiprocessing.Array('i', 100)\n"
        "def slow(i):\n"
        "    pids[i] = os.getpid()\n"
        "    time.sleep(0 if i == 0 else 30)\n"
        "    return i\n"
        "results = in_order_on_processes(slow, list(range(100)), 2, 2)\n"
        "first = next(results)\n"
        "deadline = time.time() + 10\n"
        "while len({p for p in pids[:] if p}) < 2 and time.time() < deadline:\n"
        "    time.sleep(0.01)\n"
        "busy = sorted({p for p in pids[:] if p})\n"
        "t = time.perf_counter()\n"
        "results.close()\n"
        "print(json.dumps({'first': first, 'busy': busy, 'took': time.perf_counter() - t}), flush=True)\n"
    )
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    seen = json.loads(out.stdout)
    assert seen["first"] == 0 and len(seen["busy"]) == 2, seen  # both children busy with a 30-s item
    assert seen["took"] < 5, seen  # not after the running items' 30 s
    assert not [pid for pid in seen["busy"] if _alive(pid)]


def test_stopped_children_do_not_kill_a_caller_whose_sigpipe_is_fatal(tmp_path):
    """The pool writes tasks to its children's pipe; once they are terminated (an error at
    its turn), such a write meets a closed pipe. A caller whose SIGPIPE is the default
    action (gmsh's initialize sets it so; a CI run's pytest process died with status 141)
    survives: the pool's threads hold SIGPIPE blocked. Unguarded, 20 such calls died in
    3 of 3 runs."""
    import subprocess
    import sys

    script = tmp_path / "caller.py"
    script.write_text(
        "import signal, time\n"
        "signal.signal(signal.SIGPIPE, signal.SIG_DFL)\n"
        "from railcheck.parallel.forked import in_order_on_processes\n"
        "def fail_at_3(i):\n"
        "    if i == 3:\n"
        "        raise ValueError(i)\n"
        "    time.sleep(0.05 if i < 3 else 30)\n"
        "    return i\n"
        "for _ in range(20):\n"
        "    try:\n"
        "        list(in_order_on_processes(fail_at_3, list(range(12)), 2, ahead=3))\n"
        "    except ValueError:\n"
        "        pass\n"
        "print('survived')\n"
    )
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)
    assert (out.returncode, out.stdout.strip()) == (0, "survived"), out.stderr


def test_a_caller_with_busy_threads_of_its_own_gets_the_sweep_unforked(tmp_path):
    """A library caller whose own threads run BLAS products and write to stderr while it
    sweeps: its workers are not forked (a child has only the forking thread; OpenBLAS's
    fork handler hung such a caller in blas_thread_shutdown_ in 3 of 3 runs, and a lock
    another thread holds stays held in a child), the run says so, finishes, and writes
    the serial sweep's table."""
    import subprocess
    import sys

    import pyarrow.parquet as pq

    scene = tmp_path / "kinematics.toml"
    scene.write_text('[sweep]\nkind = "both"\n')
    script = tmp_path / "caller.py"
    script.write_text(
        "import sys, threading\n"
        "import numpy as np\n"
        "from railcheck.cli import main\n"
        "stop = threading.Event()\n"
        "def products():\n"
        "    a = np.random.default_rng(0).normal(size=(200, 200))\n"
        "    while not stop.is_set():\n"
        "        a = a @ a.T / np.linalg.norm(a)\n"
        "def chatter():\n"
        "    while not stop.is_set():\n"
        "        stop.wait(0.01)\n"
        "        sys.stderr.write('caller thread\\n')\n"
        "for f in (products, chatter):\n"
        "    threading.Thread(target=f, daemon=True).start()\n"
        "status = main(['sweep', sys.argv[1], '--out', sys.argv[2], '--force'])\n"
        "stop.set()\n"
        "sys.exit(status)\n"
    )
    busy = subprocess.run(
        [sys.executable, str(script), str(scene), str(tmp_path / "busy")], capture_output=True, text=True, timeout=180
    )
    assert busy.returncode == 0, busy.stderr[-2000:]
    assert "this process runs other threads (" in busy.stderr and "its workers are not forked" in busy.stderr
    serial = subprocess.run(
        [sys.executable, "-P", "-m", "railcheck.cli", "sweep", str(scene), "--out", str(tmp_path / "serial"), "--serial"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert serial.returncode == 0, serial.stderr[-2000:]
    for kind in ("four-bar", "slider-crank"):
        name = f"sweep-{kind}.parquet"
        assert pq.read_table(tmp_path / "busy" / name).equals(pq.read_table(tmp_path / "serial" / name))


def test_a_killed_caller_leaves_no_child(tmp_path):
    """The caller killed (SIGKILL: no clean-up of its own) while its children are busy:
    the kernel ends them (``PR_SET_PDEATHSIG``)."""
    import subprocess
    import sys

    script = tmp_path / "caller.py"
    script.write_text(
        "import os, sys, time\n"
        "from railcheck.parallel.forked import in_order_on_processes\n"
        "def slow(i):\n"
        "    if i == 0:\n"
        "        return os.getpid()\n"
        "    time.sleep(60)\n"
        "for pid in in_order_on_processes(slow, list(range(10)), 2, 2):\n"
        "    print(pid, flush=True)\n"
    )
    caller = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE, text=True)
    child = int(caller.stdout.readline())
    assert os.path.exists(f"/proc/{child}")
    caller.kill()
    caller.wait(timeout=10)
    deadline = time.time() + 5
    while time.time() < deadline and _alive(child):
        time.sleep(0.05)
    assert not _alive(child)


def _alive(pid: int) -> bool:
    """Whether ``pid`` runs (a zombie awaiting its reaper does not)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def test_without_semaphores_the_platform_does_not_fork(monkeypatch):
    """A container without ``/dev/shm``: a pool's queues cannot be made, so the sweep
    keeps to threads (:func:`railcheck.parallel.forked.available` False)."""
    import multiprocessing.context

    def no_shm(self, *args, **kwargs):
        raise OSError(38, "Function not implemented")

    monkeypatch.setattr(multiprocessing.context.BaseContext, "Lock", no_shm)
    forked.available.cache_clear()
    try:
        assert not forked.available()
    finally:
        monkeypatch.undo()
        forked.available.cache_clear()
    assert forked.available()


CHILD_HEAP_SCRIPT = """
import ctypes, sys

class MallInfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in
                ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks", "fordblks", "keepcost")]

libc = ctypes.CDLL(None)
try:
    libc.mallinfo2.restype = MallInfo2
    libc.mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
except AttributeError:
    sys.exit(3)  # glibc older than 2.33, or none
# this process's threshold fixed at glibc's default (128 KiB), before anything is freed: it
# no longer adapts to what is freed, so its own 20 MB block is mapped whatever ran before
libc.mallopt(-3, 128 << 10)

import numpy as np
from railcheck.parallel.forked import in_order_on_processes

def mapped_by_a_20_mb_block(_):
    before = libc.mallinfo2().hblkhd
    block = np.ones(20 << 20, dtype=np.uint8)
    return libc.mallinfo2().hblkhd - before, int(block[-1])

grown = [g for g, _ in in_order_on_processes(mapped_by_a_20_mb_block, [0, 1], 2, ahead=1)]
print(max(grown) < (20 << 20), mapped_by_a_20_mb_block(0)[0] >= (20 << 20))
"""


def test_a_child_takes_blocks_up_to_32_mib_from_the_heap(tmp_path):
    """The children tune glibc's allocator (:func:`railcheck.parallel.forked.reuse_freed_memory`):
    a 20 MB block comes from the heap (kept and reused once freed), not from fresh
    ``mmap`` pages as in the forking process, whose threshold is held at glibc's default
    (its own block, the control)."""
    import subprocess
    import sys

    # run outside the checkout: ``-c`` puts the working directory first on the path, and a
    # checkout's ``railcheck/`` would shadow the installed package
    run = subprocess.run(
        [sys.executable, "-c", CHILD_HEAP_SCRIPT], capture_output=True, text=True, timeout=120, cwd=tmp_path
    )
    if run.returncode == 3:
        pytest.skip("no glibc mallinfo2")
    assert run.returncode == 0, run.stderr
    assert run.stdout.split() == ["True", "True"]
