"""Common behaviour of the joints' frozen result records (:class:`~gearopt.joints.press_fit.PressFitResult`,
:class:`~gearopt.joints.taper_fit.TaperFitResult`, :class:`~gearopt.joints.catalogue.JointCapacity`)."""

from __future__ import annotations

import difflib
from dataclasses import fields
from typing import Any


class ResultRecord:
    """Mixin of a frozen dataclass of results: attribute access is the typed way; ``to_dict()`` gives the fields that
    are set (optional ones left ``None`` are left out), in declaration order, for tables and plain-data hand-over. A
    misspelled attribute fails at once with the nearest valid names; string keys are refused with the attribute to
    use instead."""

    __slots__ = ()

    def to_dict(self) -> dict[str, Any]:
        """The set fields as a plain dict (``None`` fields left out), in declaration order."""
        out = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if value is not None:
                out[f.name] = value
        return out

    def __getattr__(self, name: str):
        # only called for a missing attribute: name the nearest fields
        if name.startswith("__"):
            raise AttributeError(name)
        names = [f.name for f in fields(self)]
        near = difflib.get_close_matches(name, names, n=3)
        hint = f"; did you mean {', '.join(near)}?" if near else f"; fields: {', '.join(names)}"
        raise AttributeError(f"{type(self).__name__} has no field {name!r}{hint}")

    def __getitem__(self, key):
        raise TypeError(f"{type(self).__name__} is a typed record: use attribute access (.{key}) or .to_dict()"
                        if isinstance(key, str) else f"{type(self).__name__} is not subscriptable")
