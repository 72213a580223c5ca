"""Property-based robustness suite (Hypothesis) over every public entry point of ``robustness_cases``.

The contract (issue 18): for any argument spoiled with NaN, +-inf, zero, negatives, 1e+-12, 1e300, strings, None,
bools, wrong lengths or a random float, a call either raises a typed gearopt error -- a ``GearoptInputError`` that
names the parameter when the value is not a real number, or a typed failure such as a budget hit -- or returns a
result whose numbers are all finite (``+inf`` only where documented) and plausible. Never NaN, an untyped exception
or a hang (each call is timed against ``HANG_S``; budgets make the calls terminate).

Size: examples per entry point are chosen so that the whole file runs in about 10 s in CI (derandomized, so a
failure is reproducible); ``benchmarks/bench_robustness.py`` runs the larger seeded campaign.
"""

from __future__ import annotations

import math
import time
import warnings

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import robustness_cases as rc

ENTRIES = rc.entry_points()
HANG_S = 30.0
#: Examples per entry point (simulate builds a CasADi integrator per network: fewer examples).
EXAMPLES = {"EngineExcitation": 15, "optimise_shift_split": 20, "LTCAModel": 20, "walk_off": 30, "simulate": 10,
            "Problem.solve": 50, "data file": 20, "data value": 40, "ltca": 60, "cli": 30}
DEFAULT_EXAMPLES = 60

NOT_A_NUMBER = st.one_of(st.sampled_from(["3", "abc", "", "nan"]), st.none(), st.booleans(),
                         st.tuples(st.floats(0.1, 10.0)), st.tuples(st.floats(0.1, 10.0), st.floats(0.1, 10.0),
                                                                   st.floats(0.1, 10.0)))
NUMBERS = st.one_of(st.sampled_from([math.nan, math.inf, -math.inf, 0.0, -1.0, 1e-12, 1e12, 1e300, -1e300, 2.5]),
                    st.floats(allow_nan=True, allow_infinity=True, width=64),
                    st.integers(-10 ** 6, 10 ** 6))
BAD = st.one_of(NUMBERS, NOT_A_NUMBER)


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _check_contract(entry: rc.EntryPoint, kwargs: dict, spoiled: list[str]) -> None:
    t0 = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        outcome, detail = rc.classify(entry, kwargs)
    elapsed = time.perf_counter() - t0
    assert elapsed < HANG_S, f"{entry.name} took {elapsed:.1f} s with {spoiled}: {kwargs!r:.300}"
    assert outcome in ("rejected", "typed_failure", "finite"), (
        f"{entry.name}: {outcome} with {({k: kwargs.get(k) for k in spoiled})!r:.300}: {detail}")
    values = [kwargs.get(k) for k in spoiled]
    if outcome == "rejected" and len(spoiled) == 1 and not _is_number(values[0]) and entry.name not in (
            "cli", "data file") and not (isinstance(values[0], tuple) and spoiled[0] in entry.array_ok):
        assert rc.names_parameter(detail, spoiled), f"{entry.name}: the rejection does not name {spoiled}: {detail}"


def _spoiled_kwargs(entry: rc.EntryPoint):
    """Strategy: (kwargs, spoiled names) with one or two arguments replaced."""
    names = st.lists(st.sampled_from(entry.spoilable), min_size=1, max_size=2, unique=True)

    def build(chosen):
        return st.tuples(st.just(chosen), st.lists(BAD, min_size=len(chosen), max_size=len(chosen)))

    def assemble(pair):
        chosen, values = pair
        kw = dict(entry.baseline)
        kw.update(dict(zip(chosen, values)))
        return kw, list(chosen)

    return names.flatmap(build).map(assemble)


def _settings(name: str):
    return settings(max_examples=EXAMPLES.get(name, DEFAULT_EXAMPLES), deadline=None, derandomize=True,
                    database=None, suppress_health_check=list(HealthCheck))


KEYWORD_ENTRIES = [n for n in ENTRIES if n not in ("cli", "data file", "data value")]


@pytest.mark.parametrize("name", KEYWORD_ENTRIES)
def test_spoiled_arguments_keep_the_contract(name):
    entry = ENTRIES[name]

    @_settings(name)
    @given(_spoiled_kwargs(entry))
    def check(case):
        kwargs, spoiled = case
        _check_contract(entry, kwargs, spoiled)

    check()


VALID_GEARS = st.fixed_dictionaries({
    "teeth": st.tuples(st.integers(8, 150), st.integers(8, 150)),
    "module_mm": st.floats(0.3, 25.0),
    "profile_shifts": st.tuples(st.floats(-0.6, 1.2), st.floats(-0.6, 1.2)),
    "pressure_angle_deg": st.floats(12.0, 30.0),
    "helix_angle_deg": st.one_of(st.just(0.0), st.floats(0.0, 35.0)),
    "face_width_mm": st.floats(1.0, 200.0),
})


@pytest.mark.parametrize("name", ["GearPair.check", "ltca", "contact_stress_iso6336", "root_stress_iso6336"])
def test_extreme_but_valid_gears_keep_the_contract(name):
    """Any gear from the admissible ranges: a named GeometryError, or finite results."""
    entry = ENTRIES[name]

    @settings(max_examples=15 if name == "ltca" else 25, deadline=None, derandomize=True, database=None,
              suppress_health_check=list(HealthCheck))
    @given(VALID_GEARS)
    def check(gear):
        kwargs = dict(entry.baseline)
        kwargs.update(gear)
        if name == "ltca":
            kwargs["slices"] = 1 if gear["helix_angle_deg"] == 0.0 else 5
        _check_contract(entry, kwargs, list(gear))

    check()


@settings(max_examples=EXAMPLES["cli"], deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(st.lists(st.sampled_from(rc.CLI_ARGS), min_size=1, max_size=2, unique=True),
       st.lists(st.one_of(st.sampled_from(rc.CLI_VALUES), st.text(max_size=4),
                          st.floats(allow_nan=True, allow_infinity=True).map(repr)), min_size=2, max_size=2))
def test_cli_arguments_keep_the_contract(flags, values):
    argv = ["pair", "--teeth", "38", "76", "--profile-shifts", "0.3124", "0.1118"]
    for flag, value in zip(flags, values):
        argv += [flag, value]
    if "--module-mm" not in flags:
        argv += ["--module-mm", "3"]
    _check_contract(ENTRIES["cli"], {"argv": tuple(argv)}, [f.strip("-").replace("-", "_") for f in flags])


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, float):
        return "nan" if math.isnan(v) else ("inf" if v == math.inf else "-inf" if v == -math.inf else repr(v))
    if isinstance(v, tuple):
        return "[" + ", ".join(_toml_value(e) for e in v) + "]"
    if v is None:
        return '""'
    return repr(v)


@settings(max_examples=EXAMPLES["data file"], deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(st.sampled_from(["module_mm = 3.0", "teeth = 38", "centre_distance_mm = 172.2406", "helix_angle_deg = 0.0",
                        "face_width_mm = 30.0", "pressure_angle_deg = 20.0", "stations = 6"]),
       st.one_of(BAD, st.text(max_size=6)), st.booleans())
def test_spoiled_data_files_keep_the_contract(line, value, truncate):
    """One line of the default file spoiled (or the file cut): one named DataFileError, or a sound train."""
    text = rc._default_toml().decode("utf-8")
    key = line.split(" = ")[0]
    text = text.replace(line, f"{key} = {_toml_value(value)}", 1)
    if truncate:
        text = text[: len(text) // 2]
    _check_contract(ENTRIES["data file"], {"content": text.encode("utf-8")}, [key])


@settings(max_examples=EXAMPLES["data value"], deadline=None, derandomize=True, database=None,
          suppress_health_check=list(HealthCheck))
@given(st.sampled_from(rc.DATA_PATHS), BAD)
def test_spoiled_data_values_keep_the_contract(path, value):
    _check_contract(ENTRIES["data value"], {"path": path, "value": value}, [path])


@settings(max_examples=10, deadline=None, derandomize=True, database=None, suppress_health_check=list(HealthCheck))
@given(st.binary(max_size=200))
def test_random_bytes_as_a_data_file_give_one_named_error(content):
    _check_contract(ENTRIES["data file"], {"content": content}, ["content"])
