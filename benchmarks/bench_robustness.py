"""Robustness campaign: a seeded random campaign of bad inputs over every public entry point (issue 18).

Each case spoils one or two arguments of a valid baseline call (NaN, +-inf, zero, negatives, 1e+-12, 1e300, numeric
and other strings, None, bools, wrong lengths, non-integral counts, random floats over 30 decades; damaged data
files; one spoiled value in the data; bad CLI arguments) and sorts the outcome:

- ``rejected``: a ``GearoptInputError`` (``rejected_named``: its message names the spoiled parameter);
- ``typed_failure``: another typed gearopt error (a failed solve, a budget hit);
- ``finite``: a result whose numbers are all finite (``+inf`` only where documented) and plausible;
- ``untyped``: any other exception; ``nan``: a result holding NaN or an undocumented infinity;
  ``implausible``: e.g. a negative safety factor; ``hang``: no answer within the per-call time limit.

The calls run in a worker process that is killed and restarted on a hang, so a hang costs one time limit.
The same seeded campaign runs against the gearopt of ``--baseline`` (default: the commit before issue 18's work,
exported with ``git archive``) in the same run, so the counts compare like with like. Writes
``benchmarks/results/robustness.json`` and ``robustness.png`` (``robustness_quick.*`` with ``--quick``).

    PYTHONPATH=. python benchmarks/bench_robustness.py [--quick] [--cases N] [--seed S] [--timeout-s T]
"""

from __future__ import annotations

import argparse
import io
import json
import multiprocessing as mp
import platform
import subprocess
import sys
import tarfile
import tempfile
import time
from collections import Counter, defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "robustness"))
sys.path.insert(0, str(ROOT))
if "--package" in sys.argv:  # the campaign against another gearopt tree (the baseline), before gearopt is imported
    sys.path.insert(0, sys.argv[sys.argv.index("--package") + 1])

import robustness_cases as rc  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results"
#: gearopt before issue 18 (the validation layer, budgets and data schema): the campaign's baseline.
BASELINE_COMMIT = "4e3e889"


def _worker(conn) -> None:
    import warnings
    warnings.simplefilter("ignore")
    eps = rc.entry_points()
    while True:
        msg = conn.recv()
        if msg is None:
            return
        name, kwargs = msg
        t0 = time.perf_counter()
        outcome, detail = rc.classify(eps[name], kwargs)
        conn.send((outcome, detail[:400], time.perf_counter() - t0))


class Runner:
    """A worker process that runs one call at a time and is replaced when a call exceeds the time limit."""

    def __init__(self, timeout_s: float):
        self.timeout_s = timeout_s
        self.ctx = mp.get_context("fork")
        self._start()

    def _start(self) -> None:
        self.conn, child = self.ctx.Pipe()
        self.proc = self.ctx.Process(target=_worker, args=(child,), daemon=True)
        self.proc.start()

    def run(self, name: str, kwargs: dict) -> tuple[str, str, float]:
        self.conn.send((name, kwargs))
        if self.conn.poll(self.timeout_s):
            return self.conn.recv()
        self.proc.kill()
        self.proc.join()
        self._start()
        return "hang", f"no answer within {self.timeout_s:g} s", self.timeout_s

    def close(self) -> None:
        self.conn.send(None)
        self.proc.join(5)
        if self.proc.is_alive():
            self.proc.kill()


def campaign(cases_per_entry: int, seed: int, timeout_s: float, only: list[str] | None = None) -> dict:
    rng = np.random.default_rng(seed)
    eps = {k: v for k, v in rc.entry_points().items() if not only or k in only}
    runner = Runner(timeout_s)
    table, examples, times = {}, defaultdict(list), defaultdict(list)
    try:
        for name, entry in eps.items():
            counts = Counter()
            for _ in range(cases_per_entry):
                kwargs, spoiled = rc.spoil(entry, rng)
                outcome, detail, dt = runner.run(name, kwargs)
                times[name].append(dt)
                counts[outcome] += 1
                if outcome == "rejected" and rc.names_parameter(detail, spoiled):
                    counts["rejected_named"] += 1
                if outcome in ("untyped", "nan", "implausible", "hang") and len(examples[name]) < 5:
                    examples[name].append({"spoiled": {k: repr(kwargs.get(k))[:80] for k in spoiled}
                                           if name not in ("cli", "data file", "data value") else
                                           repr(kwargs)[:200], "outcome": outcome, "detail": detail[:300]})
            table[name] = {k: counts.get(k, 0) for k in rc.OUTCOMES + ("rejected_named",)}
            table[name]["cases"] = cases_per_entry
            table[name]["median_call_s"] = float(np.median(times[name]))
            bad = sum(table[name][k] for k in ("untyped", "nan", "implausible", "hang"))
            print(f"{name:32s} " + " ".join(f"{k}={table[name][k]}" for k in rc.OUTCOMES) + f"  bad={bad}",
                  flush=True)
    finally:
        runner.close()
    totals = {k: sum(t[k] for t in table.values()) for k in rc.OUTCOMES + ("rejected_named", "cases")}
    return {"per_entry_point": table, "totals": totals, "examples": dict(examples)}


def baseline_campaign(commit: str, cases: int, seed: int, timeout_s: float) -> dict:
    """The same seeded campaign against gearopt at ``commit`` (exported with ``git archive`` to a temporary
    directory and run in a subprocess)."""
    with tempfile.TemporaryDirectory() as tmp:
        archive = subprocess.run(["git", "-C", str(ROOT), "archive", commit, "gearopt"], check=True,
                                 capture_output=True).stdout
        with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
            tar.extractall(tmp)
        out = Path(tmp) / "out"
        subprocess.run([sys.executable, __file__, "--package", tmp, "--cases", str(cases), "--seed", str(seed),
                        "--timeout-s", str(timeout_s), "--out", str(out), "--no-baseline"], check=True)
        result = json.loads((out / "robustness.json").read_text())
    result["commit"] = commit
    return result


def figure(result: dict, path: Path) -> None:
    panels = [("this version", result)] + ([(f"baseline {result['baseline']['commit'][:8]}", result["baseline"])]
                                           if result.get("baseline") else [])
    names = list(result["per_entry_point"])
    fig, axes = plt.subplots(1, len(panels), figsize=(7 * len(panels), 0.42 * len(names) + 1.8), sharey=True,
                             squeeze=False)
    for ax, (title, res) in zip(axes[0], panels):
        _panel(ax, res, names, title)
    axes[0][0].legend(ncol=7, fontsize=8, loc="upper left", bbox_to_anchor=(0.0, -0.08))
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _panel(ax, result: dict, names: list, title: str) -> None:
    table = result["per_entry_point"]
    left = np.zeros(len(names))
    colours = {"rejected": "#4c9a2a", "typed_failure": "#9ac46a", "finite": "#3a75c4", "untyped": "#d62728",
               "nan": "#ff7f0e", "implausible": "#e377c2", "hang": "#000000"}
    for outcome in rc.OUTCOMES:
        vals = np.array([table.get(n, {}).get(outcome, 0) / max(table.get(n, {}).get("cases", 1), 1)
                         for n in names])
        ax.barh(names, vals, left=left, color=colours[outcome], label=outcome)
        left += vals
    ax.set_xlabel("fraction of cases")
    ax.set_xlim(0, 1)
    if not ax.yaxis_inverted():
        ax.invert_yaxis()
    t = result["totals"]
    ax.set_title(f"{title}: {t['cases']} seeded bad-input calls\nuntyped {t['untyped']}, NaN/inf {t['nan']}, "
                 f"implausible {t['implausible']}, hang {t['hang']}", fontsize=9)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="30 cases per entry point, no baseline campaign")
    ap.add_argument("--cases", type=int, default=400, help="cases per entry point")
    ap.add_argument("--seed", type=int, default=20261124)
    ap.add_argument("--timeout-s", type=float, default=20.0, help="per-call limit before a call counts as a hang")
    ap.add_argument("--out", type=Path, default=RESULTS)
    ap.add_argument("--only", nargs="*", help="entry points to run (default: all)")
    ap.add_argument("--baseline", default=BASELINE_COMMIT,
                    help="git commit of the gearopt to run the same campaign against (default: before issue 18)")
    ap.add_argument("--no-baseline", action="store_true")
    ap.add_argument("--package", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    cases = 30 if args.quick else args.cases
    t0 = time.perf_counter()
    result = campaign(cases, args.seed, args.timeout_s, args.only)
    result.update({"seed": args.seed, "cases_per_entry_point": cases, "timeout_s": args.timeout_s,
                   "wall_s": time.perf_counter() - t0, "quick": bool(args.quick),
                   "python": platform.python_version(), "machine": platform.machine()})
    if not (args.no_baseline or args.package or args.quick):  # quick: this version only (seconds, for the tests)
        result["baseline"] = baseline_campaign(args.baseline, cases, args.seed, args.timeout_s)
    args.out.mkdir(parents=True, exist_ok=True)
    suffix = "_quick" if args.quick else ""
    (args.out / f"robustness{suffix}.json").write_text(json.dumps(result, indent=1))
    figure(result, args.out / f"robustness{suffix}.png")
    print(json.dumps(result["totals"]))
    return result


if __name__ == "__main__":
    main()
