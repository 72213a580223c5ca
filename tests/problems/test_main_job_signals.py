"""Issue 29 (item 7): a SIGTERM to the running main job (a timeout, a scheduler, kill) leaves no process of its tree
running: the side processes, their workers and the figure writer end with it, and the exit code (143) is not a
failed requirement's (1)."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import psutil

SCRIPT = Path(__file__).resolve().parents[2] / "problems" / "cam_gear_walkoff.py"


def _running(p: "psutil.Process") -> bool:
    try:
        return p.is_running() and p.status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


def test_sigterm_ends_the_whole_process_tree(tmp_path):
    proc = subprocess.Popen([sys.executable, str(SCRIPT), "--quick", "--out", str(tmp_path)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env={**os.environ})
    try:
        parent = psutil.Process(proc.pid)
        tree: dict[int, psutil.Process] = {}
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and proc.poll() is None:   # until the side processes and the figure
            for child in parent.children(recursive=True):             # writer run
                tree.setdefault(child.pid, child)
            if len(tree) >= 3:
                break
            time.sleep(0.2)
        assert len(tree) >= 2, "the main job did not start its side processes"
        time.sleep(1.0)
        for child in parent.children(recursive=True):                 # the workers' own children too
            tree.setdefault(child.pid, child)
        proc.send_signal(signal.SIGTERM)
        code = proc.wait(timeout=60)         # a long C call (a solve) delays the handler
        # none of the tree running 10 s later (a process that has ended stays ended: poll instead of sleeping)
        deadline = time.monotonic() + 10.0
        while True:
            alive = [p.pid for p in tree.values() if _running(p)]
            if not alive or time.monotonic() > deadline:
                break
            time.sleep(0.2)
        assert alive == [], f"processes of the job's tree still running 10 s after SIGTERM: {alive}"
        assert code == 128 + signal.SIGTERM, proc.stderr.read().decode()[-2000:]
    finally:
        if proc.poll() is None:
            proc.kill()


def test_a_dead_side_process_is_one_line_naming_its_stage():
    from concurrent.futures import Future
    from concurrent.futures.process import BrokenProcessPool

    import pytest
    from conftest import load_script

    from gearopt.cli import run_script

    future: Future = Future()
    future.set_exception(BrokenProcessPool("A process in the process pool was terminated abruptly"))
    job = load_script("cam_gear_walkoff")
    with pytest.raises(RuntimeError, match="stage codesign_nlp: its side process died"):
        job.side_result("codesign_nlp", future)

    def dies(argv):
        job.side_result("codesign_nlp", future)
    assert run_script(dies) == 3                    # an internal error's code, not a failed requirement's 1
