"""Plain-text tables: DataFrames to Markdown (no extra dependency) and to CSV, written side by side."""

from __future__ import annotations

import math
from typing import Any
from pathlib import Path

import pandas as pd


def eng(value: Any, digits: int = 3) -> str:
    """A number at engineering precision: ``digits`` significant figures, no exponent between 1e-3 and 1e6
    (``inf`` and strings pass through)."""
    if isinstance(value, str):
        return value
    v = float(value)
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    if math.isnan(v):
        return "n/a"
    if v == 0.0:
        return "0"
    if not 1e-3 <= abs(v) < 1e6:
        return f"{v:.{digits - 1}e}"
    decimals = max(digits - 1 - int(math.floor(math.log10(abs(v)))), 0)
    return f"{round(v, decimals):.{decimals}f}"


def _fmt(v, digits: int) -> str:
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        if math.isnan(v):
            return ""
        if v != 0.0 and (abs(v) >= 1e6 or abs(v) < 10 ** (-digits)):
            return f"{v:.{digits}g}"
        return f"{v:.{digits}f}"
    return str(v)


def to_markdown(df: pd.DataFrame, digits: int = 4) -> str:
    """A GitHub-flavoured Markdown table of ``df`` (index included when named)."""
    frame = df.reset_index() if df.index.name is not None else df
    header = [str(c) for c in frame.columns]
    rows = [[_fmt(v, digits) for v in row] for row in frame.itertuples(index=False, name=None)]
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines)


def write_table(df: pd.DataFrame, directory: str | Path, stem: str, digits: int = 6) -> Path:
    """Write ``<stem>.csv`` into ``directory`` (created if needed) and return its path."""
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    path = d / f"{stem}.csv"
    df.to_csv(path, float_format=f"%.{digits}g")
    return path
