"""The suite's xdist scheduling (tests/conftest.py) names units that exist: a renamed file or test would silently
lose its early start."""

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def schedule():
    spec = importlib.util.spec_from_file_location("suite_schedule", ROOT / "tests" / "conftest.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_listed_unit_exists(request):
    s = schedule()
    collected = {item.nodeid for item in request.session.items}
    for entry in s.LONGEST_FIRST:
        path, _, test = entry.partition("::")
        assert (ROOT / path).is_file(), entry
        if test and collected and any(i.startswith(path + "::") for i in collected):   # its file collected here
            assert entry in collected, entry
    assert all((ROOT / p).is_file() for p in s.PER_TEST)


def test_rank_puts_listed_units_first_in_their_order():
    s = schedule()
    units = ["tests/test_cli.py", *reversed(s.LONGEST_FIRST)]
    ranked = sorted(units, key=s.rank)
    assert ranked[:-1] == list(s.LONGEST_FIRST) and ranked[-1] == "tests/test_cli.py"
    assert s.rank("tests/problems/test_helix_front_script.py::test_front_makes_physical_sense") == 0


class Config:
    """The parts of a pytest config xdist's file scheduler reads: two workers, ``--dist`` as given."""

    def __init__(self, dist: str):
        self.dist = dist
        self.option = type("Option", (), {"loadscopereorder": True})()

    def getvalue(self, name):
        return {"dist": self.dist, "tx": ["2*popen"]}[name]


class Worker:
    """A worker that records the test indexes sent to it."""

    def __init__(self, name: str):
        self.sent, self.shutting_down = [], False
        self.gateway = type("Gateway", (), {"id": name})()

    def send_runtest_some(self, indexes):
        self.sent.extend(indexes)

    def shutdown(self):
        self.shutting_down = True


def test_loadfile_starts_the_longest_units_and_splits_independent_files():
    collection = ["tests/test_cli.py::test_a", "tests/test_cli.py::test_b", "tests/test_cli.py::test_c",
                  "tests/problems/test_cam_gear_walkoff.py::test_outputs_written",
                  "tests/test_readme.py::test_readme_block_runs_alone[2]",
                  "tests/test_readme.py::test_docs_example_runs_alone[2]",
                  "tests/problems/test_helix_front_script.py::test_outputs_and_every_point_with_a_status",
                  "tests/problems/test_helix_front_script.py::test_front_makes_physical_sense"]
    scheduler = schedule().pytest_xdist_make_scheduler(Config("loadfile"), None)
    workers = [Worker("gw0"), Worker("gw1")]
    for w in workers:
        scheduler.add_node(w)
        scheduler.add_node_collection(w, collection)
    scheduler.schedule()
    first = [collection[w.sent[0]].split("::")[0] for w in workers]
    assert first == ["tests/problems/test_helix_front_script.py", "tests/problems/test_cam_gear_walkoff.py"]
    sent = sorted(i for w in workers for i in w.sent)   # two units each to start (xdist's rule): the unlisted
    assert sent == list(range(3, len(collection)))      # file waits, every other test is sent once
    readme = [collection.index(n) for n in collection if n.startswith("tests/test_readme.py")]
    assert any(readme[0] in w.sent and readme[1] not in w.sent for w in workers)   # one unit per README block
    assert schedule().pytest_xdist_make_scheduler(Config("load"), None) is None
