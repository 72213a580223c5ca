"""Cases: studies of one particular system, built on the library and kept apart from it.

The library (everything outside this package) knows no gear, mesh or joint by name: it takes the names from the
user's :class:`~gearopt.data.System`. A case is where a specific system's set-up lives -- its model of the engine,
the meshes and joints its studies look at, the baselines it compares with, the summary of its main job.

- :mod:`gearopt.cases.timing_train`: the packaged diesel engine's timing gear train (the source study: a helical
  cam gear walked off its shaft; the cure is a spur train in the same housing), run by
  ``problems/cam_gear_walkoff.py``.
"""

__all__: list[str] = []
