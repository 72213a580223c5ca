"""The model store of one scene build: every model under its key (``family:target``), built at its first request
and only then, with a log of what was built, in order, with details and build times.

Shared by the parts of a built scene (:class:`~gearopt.design.scene_inputs.SceneInputs` for the data set and the
dynamic load cases, :class:`~gearopt.design.scene_models.SceneModels` and
:class:`~gearopt.design.scene_contact.ContactModels` for the model graph), so each model is built once per target
whichever part asks first; a re-build (the refinement's) may take over models that do not depend on its changes
(``reuse``: taken over unbuilt, not in the log).
"""

from __future__ import annotations

import time
from typing import Any, Callable, Mapping

import pandas as pd


class ModelCache:
    """Models by key (:attr:`models`), each built once by :meth:`get`; :attr:`built` and :attr:`build_table` say
    what was built here (models taken over by ``reuse`` are in :attr:`models`, not in the log)."""

    def __init__(self, reuse: Mapping[str, Any] | None = None):
        self.models: dict[str, Any] = dict(reuse or {})
        self._log: list[dict[str, Any]] = []

    def get(self, key: str, build: Callable[[], Any], detail: Callable[[Any], str] | str = "") -> Any:
        """The model under ``key``, built by ``build()`` at the first request (``detail``: a string or a function
        of the model for the build table)."""
        if key not in self.models:
            t0 = time.perf_counter()
            obj = build()
            self.models[key] = obj
            self._log.append({"model": key, "detail": detail(obj) if callable(detail) else detail,
                              "build_time_s": time.perf_counter() - t0})
        return self.models[key]

    @property
    def built(self) -> list[str]:
        """Keys of the models built, in build order (``family:target``)."""
        return [r["model"] for r in self._log]

    @property
    def build_table(self) -> pd.DataFrame:
        """One row per built model: ``model``, ``detail`` (settings), ``build_time_s``."""
        return pd.DataFrame(self._log, columns=["model", "detail", "build_time_s"])


__all__ = ["ModelCache"]
