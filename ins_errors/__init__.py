"""ins-errors: error analysis of inertial navigation systems.

Quick start::

    import ins_errors
    model = ins_errors.load_model("orthodromic")
    model.sources          # error sources with units and meaning
    F = model.state_matrix(x, u)   # linear error equations, numpy
    own = ins_errors.load_model("my_ins.py")   # a model file (ins_errors.modeling)

See README.md for the tour, ``docs/api.md`` for the Python API (what to import for each
task, units and shapes, the exceptions and warnings), ``generated/<model>/error_equations.md``
for the equations and ``examples/own_model/`` for writing a model of your own.

Every error a user can provoke with bad input is an :class:`InsErrorsError` (a
``ValueError``) with a one-line message; the error classes of the modules
(:class:`MotionError`, :class:`UnitError`, ...) are importable from here.
"""

from ins_errors.errors import (
    DomainError,
    InsErrorsError,
    InsErrorsNotice,
    InsErrorsWarning,
    ModelDefinitionError,
    ShapeError,
    UnknownNameError,
)

_FROM_MODEL = ("Info", "Model", "available_models", "load_model")
"""Names of :mod:`ins_errors.numeric.model` read on first use: importing the package
(as the ``ins-errors`` command does before anything else) stays light (no numpy), so the
command sets its SIGTERM handler within milliseconds of starting."""

_ERRORS = {
    "CovarianceError": "ins_errors.analysis.covariance",
    "LinearSystemError": "ins_errors.numeric.linear_system",
    "MotionError": "ins_errors.numeric.trajectories",
    "StepError": "ins_errors.numeric.integrators",
    "UnitError": "ins_errors.units",
}
"""The error classes of the modules that raise them, exported here too and imported on
first use for the same reason (their modules import numpy, SciPy or pint)."""


def __getattr__(name: str):
    if name in _FROM_MODEL:
        from ins_errors.numeric import model

        value = getattr(model, name)
    elif name in _ERRORS:
        import importlib

        value = getattr(importlib.import_module(_ERRORS[name]), name)
    else:
        raise AttributeError(f"module 'ins_errors' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted({*globals(), *_FROM_MODEL, *_ERRORS})


__all__ = [
    "CovarianceError",
    "DomainError",
    "Info",
    "InsErrorsError",
    "InsErrorsNotice",
    "InsErrorsWarning",
    "LinearSystemError",
    "Model",
    "ModelDefinitionError",
    "MotionError",
    "ShapeError",
    "StepError",
    "UnitError",
    "UnknownNameError",
    "available_models",
    "load_model",
]
__version__ = "0.1.0"
