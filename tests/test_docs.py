"""Documentation that ships: nothing in the package, scripts, README, tests or docs points readers to a document the
repository does not contain, and every ``docs/*.md`` that is cited exists."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# background files of the development set-up that are not part of the repository
UNSHIPPED = re.compile(r"DESIGN\.md|REFERENCE-DATA|\.\./shared|shared/reference|/work/")


def _shipped_text_files():
    for folder in ("gearopt", "problems", "benchmarks", "tests", "docs"):
        for path in (ROOT / folder).rglob("*"):
            if path.suffix in {".py", ".md", ".toml"} and path != Path(__file__).resolve():
                yield path
    yield ROOT / "README.md"


def test_no_reference_to_unshipped_documents():
    hits = [f"{p.relative_to(ROOT)}:{i}: {line.strip()[:80]}" for p in _shipped_text_files()
            for i, line in enumerate(p.read_text(errors="replace").splitlines(), 1) if UNSHIPPED.search(line)]
    assert not hits, "references to documents that do not ship:\n" + "\n".join(hits)


def test_cited_docs_exist():
    cited = {m for p in _shipped_text_files() for m in re.findall(r"docs/[\w.-]+\.md", p.read_text(errors="replace"))}
    assert cited, "expected the data sources to cite docs/"
    missing = sorted(c for c in cited if not (ROOT / c).is_file())
    assert not missing, f"cited but missing: {missing}"
