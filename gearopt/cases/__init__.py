"""Cases: studies of one particular system, built on the library and kept apart from it.

The library (everything outside this package) knows no gear, mesh or joint by name: it takes the names from the
user's :class:`~gearopt.data.System`. A case is where a specific system's set-up lives -- its model of the engine,
the meshes and joints its studies look at, the baselines it compares with, the summary of its main job.

- :mod:`gearopt.cases.timing_train`: the packaged diesel engine's timing gear train (the source study: a helical
  cam gear walked off its shaft; the cure is a spur train in the same housing), run by
  ``problems/cam_gear_walkoff.py``.
"""


def torsional_model(system, kind: str = "spur", **options):
    """The torsional model of a :class:`~gearopt.data.System`: the timing-train case's engine model for a system
    driven by an ``[engine]`` (:func:`gearopt.cases.timing_train.timing_model`), else the generic train model of
    its ``[excitation]`` (:func:`gearopt.dynamics.train_model`; a system with neither raises
    :class:`~gearopt.errors.MissingSectionError` naming the file and ``[excitation]``). ``options`` go to the
    model's builder."""
    if system.excitation == "engine":
        from .timing_train import timing_model   # imported here: the case loads only for an engine's system
        return timing_model(system, kind, **options)
    from ..dynamics import train_model
    return train_model(system, kind, **options)


__all__ = ["torsional_model"]
