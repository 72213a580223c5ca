"""Validation of gearopt's macro-geometry against published worked examples.

The cases (inputs, published outputs, tolerances implied by the printed precision, sources) live in
``published_geometry_cases.py``. Each published number is one test, named ``<case id>::<key>[gear]``, so a failure
points at exactly one quantity of one example. Cases whose numbers could not be re-read from the source while they
were recorded carry ``retrieved_in_session = False`` in their source; a failure there is reported with that flag.
"""

from __future__ import annotations

import math
import os
import sys
from functools import lru_cache

import pytest

sys.path.insert(0, os.path.dirname(__file__))

from published_geometry_cases import CASES  # noqa: E402

import gearopt as go  # noqa: E402

# Published numbers carry up to 10 decimals; allow a relative floor well below any engineering significance so that
# an inverse-involute solve converged to ~1e-12 is not failed on the 11th digit.
RELATIVE_FLOOR = 1.0e-9

_BY_ID = {c["id"]: c for c in CASES}


@lru_cache(maxsize=None)
def _geometry(case_id: str) -> dict:
    case = _BY_ID[case_id]
    constructor = getattr(go.GearPair, case["constructor"])
    pair = constructor(**case["inputs"])
    return pair.geometry()


def _to_float(value) -> float:
    try:
        return float(value)
    except TypeError:  # e.g. a 1x1 CasADi DM or numpy array
        import numpy as np

        return float(np.asarray(value, dtype=float).reshape(-1)[0])


def _actual_component(value, gear_index):
    """Return gear ``gear_index`` (0/1) of a per-gear value; a scalar applies to both gears; None -> scalar."""
    if gear_index is None:
        if isinstance(value, (tuple, list)):
            # a scalar published value compared with a per-gear result (e.g. whole depth): both must match
            return [_to_float(v) for v in value]
        return [_to_float(value)]
    if isinstance(value, (tuple, list)):
        return [_to_float(value[gear_index])]
    return [_to_float(value)]


def _params():
    out = []
    for case in CASES:
        for key, spec in case["expected"].items():
            if isinstance(spec, tuple):
                for gear_index, sub in enumerate(spec):
                    if sub is not None:
                        out.append(pytest.param(case["id"], key, gear_index, sub,
                                                id=f"{case['id']}::{key}[{gear_index + 1}]"))
            else:
                out.append(pytest.param(case["id"], key, None, spec, id=f"{case['id']}::{key}"))
    return out


@pytest.mark.parametrize("case_id, key, gear_index, spec", _params())
def test_published_value(case_id, key, gear_index, spec):
    case = _BY_ID[case_id]
    geometry = _geometry(case_id)
    assert key in geometry, f"geometry() has no key {key!r} (available: {sorted(geometry)})"
    expected = spec["value"]
    tol = max(spec["abs_tol"], RELATIVE_FLOOR * abs(expected))
    for actual in _actual_component(geometry[key], gear_index):
        assert math.isfinite(actual), f"{key} is not finite: {actual}"
        gear = "" if gear_index is None else f" (gear {gear_index + 1})"
        flag = "" if case["source"]["retrieved_in_session"] else \
            " [source numbers not re-read in session: check the page before blaming the library]"
        assert abs(actual - expected) <= tol, (
            f"{case_id}: {key}{gear} = {actual!r}, published {spec['printed']} -> |diff| = "
            f"{abs(actual - expected):.3g} > tol {tol:.3g}; source: {case['source']['url']} "
            f"({case['source']['locator']}){flag}")


def test_cases_have_sources_and_tolerances():
    """Data hygiene: every case names its source and every expected spec has a positive tolerance."""
    for case in CASES:
        assert case["source"]["url"].startswith("http"), case["id"]
        assert case["constructor"] in ("from_profile_shifts", "from_centre_distance"), case["id"]
        specs = []
        for spec in case["expected"].values():
            specs.extend(s for s in (spec if isinstance(spec, tuple) else (spec,)) if s is not None)
        assert specs, case["id"]
        assert all(s["abs_tol"] > 0.0 for s in specs), case["id"]
