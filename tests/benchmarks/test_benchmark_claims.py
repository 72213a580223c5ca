"""The benchmark README's claims are the JSON results' numbers: benchmarks/claims.py renders them, and the README
must hold exactly that block (re-run ``python benchmarks/claims.py`` after re-running a benchmark)."""

import importlib.util
from pathlib import Path

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"


def _claims():
    spec = importlib.util.spec_from_file_location("benchmark_claims", BENCHMARKS / "claims.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_readme_claims_are_generated_from_the_results():
    claims = _claims()
    text = (BENCHMARKS / "README.md").read_text()
    assert claims.START in text and claims.END in text
    assert claims.readme_block(text) == claims.render(), "benchmarks/README.md is stale: run benchmarks/claims.py"


def test_every_results_file_has_its_claim():
    block = _claims().render()
    for path in (BENCHMARKS / "results").glob("*.json"):
        if path.stem != "dynamics":   # bench_dynamics.py: integrator study, its figures are the claim
            assert f"`{path.name}`" in block and "not run yet" not in block.split(f"`{path.name}`")[1][:20]
