"""The executor of the studies: :mod:`gearopt.executor` (a bottom-layer unit, so that dynamics and design batches use
it too), re-exported here under its public studies name."""

from ..executor import (KINDS, Executor, _NoBar, _process_context, _progress_bar, get_executor,  # noqa: F401
                        using_executor)

__all__ = ["Executor", "get_executor", "using_executor", "KINDS"]
