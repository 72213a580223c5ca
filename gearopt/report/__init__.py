"""Reports: tables engineers can read (Markdown, CSV) and the macro-design tables of the thesis scene."""

from .tables import to_markdown, write_table

__all__ = ["to_markdown", "write_table"]
