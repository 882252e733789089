"""ins-errors: error analysis of inertial navigation systems.

Quick start::

    import ins_errors
    model = ins_errors.load_model("orthodromic")
    model.sources          # error sources with units and meaning
    F = model.state_matrix(x, u)   # linear error equations, numpy
    own = ins_errors.load_model("my_ins.py")   # a model file (ins_errors.modeling)

See README.md for the tour and ``generated/<model>/error_equations.md`` for the equations;
``examples/own_model/`` for writing a model of your own.
"""

from ins_errors.errors import DomainError, InsErrorsError, ShapeError, UnknownNameError

_FROM_MODEL = ("Info", "Model", "available_models", "load_model")
"""Names of :mod:`ins_errors.numeric.model` read on first use: importing the package
(as the ``ins-errors`` command does before anything else) stays light (no numpy), so the
command sets its SIGTERM handler within milliseconds of starting."""


def __getattr__(name: str):
    if name in _FROM_MODEL:
        from ins_errors.numeric import model

        value = getattr(model, name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'ins_errors' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_FROM_MODEL})


__all__ = [
    "DomainError",
    "Info",
    "InsErrorsError",
    "Model",
    "ShapeError",
    "UnknownNameError",
    "available_models",
    "load_model",
]
__version__ = "0.1.0"
