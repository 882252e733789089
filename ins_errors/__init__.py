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
from ins_errors.numeric.model import Info, Model, available_models, load_model

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
