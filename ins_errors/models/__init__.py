"""SymPy definitions of the INS models, one module per model.

``definition(name)`` builds (and caches) a model's :class:`~ins_errors.modeling.ModelDefinition`.
Importing this package does not import SymPy-heavy model modules until asked.
"""

from __future__ import annotations

import importlib
from functools import cache
from typing import TYPE_CHECKING

from ins_errors.errors import unknown_name

if TYPE_CHECKING:
    from ins_errors.modeling import ModelDefinition

MODEL_MODULES: dict[str, str] = {
    "orthodromic": "ins_errors.models.orthodromic",
    "north_pointing": "ins_errors.models.north_pointing",
    "free_azimuth": "ins_errors.models.free_azimuth",
    "geodetic_vertical": "ins_errors.models.geodetic_vertical",
    "strapdown_ned": "ins_errors.models.strapdown_ned",
}
"""Registry: model name -> module whose ``build()`` returns its definition."""


def model_names() -> list[str]:
    """Names of every registered model."""
    return list(MODEL_MODULES)


@cache
def definition(name: str) -> ModelDefinition:
    """The symbolic definition of model ``name``.

    Raises
    ------
    UnknownNameError
        If no model of that name is registered.
    """
    if name not in MODEL_MODULES:
        raise unknown_name("model", name, MODEL_MODULES)
    return importlib.import_module(MODEL_MODULES[name]).build()
