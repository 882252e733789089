"""A loaded model: names, generated numeric functions, validated evaluation.

``load_model(name)`` imports only the generated code (no SymPy): fast, and it works from
an installed wheel. The SymPy definition is built on first access to ``.symbolic``.
``load_model`` also takes a model file (``"./my_ins.py"``) or an installed entry point
(see :mod:`ins_errors.model_lookup`); their generated code is found or derived there. A
built-in model edited since ``make derive`` is derived again into the cache, said in one
line (:mod:`ins_errors.builtin_packages`).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache, cached_property
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from ins_errors.errors import DomainError, InsErrorsError, ShapeError, unknown_name


@dataclass(frozen=True)
class Info:
    """Public description of one named quantity of a model.

    Attributes
    ----------
    name : str
        Stable public identifier.
    unit : str
        SI unit.
    description : str
        One-line meaning.
    latex : str
        LaTeX symbol.
    default : float or None
        Default value (parameters only).
    kind : str or None
        ``"constant"`` or ``"initial"`` (error sources only).
    display_unit : str or None
        Unit the quantity is usually quoted in (error sources only).
    factor : int or None
        Lab-manual factor number (error sources only).
    damping_gain : bool
        A gain of a damping loop, 0 leaving the loop open (parameters only;
        :attr:`ins_errors.modeling.Parameter.damping_gain`).
    example : str
        A value to suggest with its unit, as typed after ``-p NAME=``; empty: none
        (parameters only).
    example_gives : str
        What the example gives (``"a 300-s loop, damping 0.7"``); empty: nothing said.
    """

    name: str
    unit: str
    description: str
    latex: str
    default: float | None = None
    kind: str | None = None
    display_unit: str | None = None
    factor: int | None = None
    damping_gain: bool = False
    example: str = ""
    example_gives: str = ""


def _infos(rows: tuple[dict[str, Any], ...]) -> tuple[Info, ...]:
    return tuple(Info(**row) for row in rows)


KINDS = ("states", "error_states", "inputs", "parameters", "sources", "outputs",
         "initial_conditions")
"""The kinds of named quantities of a model (:meth:`Model.index`)."""


def as_model(model: Any, function: str) -> Model:
    """``model`` itself if it is a :class:`Model`, else the model of that name loaded.

    Raises
    ------
    InsErrorsError
        If ``model`` is neither a Model nor a name (or the name is unknown).
    """
    if isinstance(model, Model):
        return model
    if isinstance(model, str | Path):
        return load_model(str(model))
    raise InsErrorsError(f"{function}: model must be a Model (ins_errors.load_model(name)) "
                         f"or a model name, got {type(model).__name__}")


def _latitude_rows(infos: tuple[Info, ...]) -> tuple[int, ...]:
    """Positions of the quantities described as a latitude (in rad)."""
    return tuple(k for k, i in enumerate(infos)
                 if i.unit == "rad" and "latitude" in i.description.lower())


def available_models() -> tuple[str, ...]:
    """Names of every built-in model and every model installed packages register
    (entry-point group ``ins_errors.models``)."""
    from ins_errors.model_lookup import builtin_names, entry_point_names

    return (*builtin_names(), *entry_point_names())


def load_model(name: str | Model, relative_to: str | Path | None = None) -> Model:
    """Load a model's generated code and metadata.

    Parameters
    ----------
    name : str or Model
        Model name (``"orthodromic"``), model file (``"./my_ins.py"``), installed
        entry-point name, or a :attr:`Model.key`; a loaded :class:`Model` is returned as
        it is.
    relative_to : path, optional
        Folder a relative model file is taken from (default: the current folder).

    Raises
    ------
    UnknownNameError
        If there is no such model (the message suggests close names).
    ModelDefinitionError
        If a model file has a mistake (one line naming the quantity and the step).
    """
    if isinstance(name, Model):  # already loaded: the same object
        return name
    from ins_errors.model_lookup import resolve

    ref = resolve(name, relative_to)
    if ref.kind == "builtin":  # its shipped package, or, if its model was edited since
        from ins_errors.builtin_packages import builtin_model  # `make derive`, a fresh one

        return builtin_model(ref.spec)
    return _file_model(ref)


@cache
def _file_model(ref) -> Model:
    from ins_errors.model_lookup import definition_of, generated_folder, load_module

    folder = generated_folder(ref)
    prefix = f"_ins_errors_generated_{ref.sha256[:16]}"
    meta = load_module(folder / "__init__.py", prefix)
    numpy_module = load_module(folder / "numpy_model.py", f"{prefix}_numpy")
    casadi_module = load_module(folder / "casadi_model.py", f"{prefix}_casadi")  # cheap
    return Model(meta.NAME, meta=meta, numpy_module=numpy_module,
                 casadi_loader=lambda: casadi_module,
                 definition_loader=lambda: definition_of(ref), key=ref.key, folder=folder)


def si_number(value: Any, what: str, unit: str, error: type[InsErrorsError] = InsErrorsError,
              shape_error: type[InsErrorsError] = ShapeError) -> float:
    """One real number in SI ``unit`` (the Python API takes no text with units), or a
    one-line ``error`` naming ``what`` (``shape_error`` for an array or a complex value)."""
    if isinstance(value, str):
        raise error(f"{what} takes a number in SI units ({unit}), got {value!r:.40}; "
                    f"convert text with ins_errors.units.parse_quantity({value!r:.40}, "
                    f"{unit!r})")
    if np.ndim(value) != 0 or np.iscomplexobj(value):
        raise shape_error(f"{what} must be one real number ({unit}), got {value!r:.60}")
    try:
        return float(value)
    except (TypeError, ValueError):
        raise error(f"{what} must be a number ({unit}), got {value!r:.60}") from None


def _verb(what: str) -> str:
    """``contain`` after plural names (``inputs u``, ``parameters``, ``error sources w``),
    ``contains`` after singular ones (``state x``, ``real state xr``)."""
    words = what.rsplit(": ", 1)[-1].split()
    noun = words[-2] if len(words) > 1 and len(words[-1]) <= 2 else words[-1]
    return "contain" if noun.endswith("s") else "contains"


class Model:
    """A model's names, generated numeric functions and validated evaluators.

    The evaluators (``state_matrix``, ``ideal_rhs``, ...) check argument shapes, finite
    values and the model's domain (e.g. latitude at a pole) and raise a one-line
    :class:`~ins_errors.errors.InsErrorsError`; then they call the generated numpy code.
    Arguments may carry trailing batch axes (shape ``(n, ...)``). Everything is SI
    (angles in rad).

    Attributes
    ----------
    name, title, source_document : str
        The model's name, title and the document it follows.
    states, error_states, inputs, parameters, sources, outputs, initial_conditions : tuple
        The named quantities (``.name``, ``.unit`` (SI), ``.description``, ...), in the
        order of the vectors and matrix rows the evaluators take and return: ``x``
        (n), ``xe`` (ne: the errors of the states, then the platform angles or other
        extra error states), ``u``, ``p``, ``w`` (the error sources, G's columns), ``y``
        and ``c``; :meth:`index` finds a name's position.
    key : str
        What :func:`load_model` maps back to this exact model (also what it is pickled
        as). Two models compare (and hash) equal when they have the same key and
        were derived from the same sources: ``load_model("strapdown_ned") ==
        pickle.loads(pickle.dumps(model))``.
    mode_notes : dict of str to str
        Why a static-base mode is not at its textbook value, when the mechanisation makes
        it so (:attr:`ins_errors.modeling.ModelDefinition.mode_notes`; ``ins-errors
        modes`` prints it); empty for most models.
    """

    def __init__(self, name: str, *, meta: ModuleType | None = None,
                 numpy_module: ModuleType | None = None,
                 casadi_loader: Callable[[], ModuleType] | None = None,
                 definition_loader: Callable[[], Any] | None = None, key: str | None = None,
                 folder: Path | None = None):
        self.name = name
        self.key: str = key or name
        """What :func:`load_model` maps back to this exact model (its name for a built-in
        model; file path and hash for a model file)."""
        self.folder: Path | None = folder
        """Folder of the generated package of a model file, or of a built-in model
        derived again into the cache (its model edited since `make derive`); None for a
        built-in model's shipped package."""
        package = f"ins_errors.generated.{name}"
        self.meta = meta or importlib.import_module(package)
        self.numpy: ModuleType = numpy_module or importlib.import_module(
            f"{package}.numpy_model")
        self._casadi_loader = casadi_loader or (
            lambda: importlib.import_module(f"{package}.casadi_model"))
        self._definition_loader = definition_loader
        self.title: str = self.meta.TITLE
        self.source_document: str = self.meta.SOURCE
        self.states = _infos(self.meta.STATES)
        self.error_states = _infos(self.meta.ERROR_STATES)
        self.inputs = _infos(self.meta.INPUTS)
        self.parameters = _infos(self.meta.PARAMETERS)
        self.sources = _infos(self.meta.SOURCES)
        self.outputs = _infos(self.meta.OUTPUTS)
        self.initial_conditions = _infos(self.meta.INITIAL_CONDITIONS)
        self.mode_notes: dict[str, str] = dict(getattr(self.meta, "MODE_NOTES", {}))

    def __reduce__(self):
        """Pickled as its :attr:`key`, loaded again (the generated modules it holds are
        not picklable): a process pool's worker gets the same model, a model file's
        exact version included."""
        return load_model, (self.key,)

    @property
    def _identity(self) -> tuple:
        """What makes two loaded models the same model: the :attr:`key` (a model file's
        includes the SHA-256 of its content) and the hashes of the sources a built-in
        model's code was derived from (a built-in model edited since ``make derive`` is
        derived again into the cache: another model under the same name)."""
        sources = getattr(self.meta, "MODEL_SOURCES_SHA256", None) or {}
        return self.key, tuple(sorted(sources.items()))

    def __eq__(self, other: object) -> bool:
        """Two models are equal when they are the same model definition (:attr:`key`
        and the sources' hashes), however often it was loaded or unpickled."""
        if not isinstance(other, Model):
            return NotImplemented
        return self._identity == other._identity

    def __hash__(self) -> int:
        return hash(self._identity)

    def __repr__(self) -> str:
        return (f"<Model {self.name!r}: {len(self.states)} states, {len(self.error_states)} "
                f"error states, {len(self.sources)} error sources, {len(self.outputs)} outputs>")

    # -- lazily loaded views ------------------------------------------------------------
    @cached_property
    def casadi(self) -> ModuleType:
        """The generated CasADi module (``.function(name)`` returns a ``casadi.Function``)."""
        return self._casadi_loader()

    @cached_property
    def symbolic(self):
        """The SymPy :class:`~ins_errors.modeling.ModelDefinition` (imports SymPy)."""
        if self._definition_loader is not None:
            return self._definition_loader()
        from ins_errors.models import definition

        return definition(self.name)

    @property
    def has_small_angle_platform(self) -> bool:
        """True for a model whose platform kinematics a direct run chooses (``platform=
        "exact"`` or ``"small_angle"``, the source documents' matrix): derive generates
        ``real_rhs_small_angle`` exactly for a definition with ``small_angle_rhs``
        (:attr:`ins_errors.modeling.ModelDefinition.has_small_angle_platform`)."""
        return "real_rhs_small_angle" in self.numpy.FUNCTIONS

    @cached_property
    def _real_states(self) -> tuple[Info, ...]:
        """The real work's state: the computed states, then the platform angles."""
        n = len(self.states)
        return self.states + self.error_states[n:]

    @cached_property
    def _state_latitudes(self) -> tuple[int, ...]:
        return _latitude_rows(self.states)

    @cached_property
    def _initial_latitudes(self) -> tuple[int, ...]:
        return _latitude_rows(self.initial_conditions)

    # -- names --------------------------------------------------------------------------
    @staticmethod
    def _names(infos: tuple[Info, ...]) -> list[str]:
        return [i.name for i in infos]

    def index(self, kind: str, name: str) -> int:
        """Position of ``name`` among the model's ``kind`` (``"sources"``, ``"outputs"``...)."""
        if kind not in KINDS:
            raise unknown_name("kind of quantity", str(kind), KINDS)
        infos = getattr(self, kind)
        names = self._names(infos)
        if name not in names:
            raise unknown_name(f"{kind.rstrip('s').replace('_', ' ')} of {self.name}", name, names)
        return names.index(name)

    def source(self, name: str) -> Info:
        """Description of the error source ``name``."""
        return self.sources[self.index("sources", name)]

    # -- vectors ------------------------------------------------------------------------
    def parameter_vector(self, ellipsoid: str | None = None, **overrides: float) -> np.ndarray:
        """Parameter vector ``p`` (SI): the model's defaults, an Earth shape, overrides.

        Parameters
        ----------
        ellipsoid : str, optional
            ``"krasovsky"`` or ``"wgs84"``: sets the semi-major axis and eccentricity
            (parameters ``a``/``e2``, or ``R``/``ecc2`` for models that default to a
            sphere). ``None`` keeps the model's own default Earth.
        **overrides : float
            Any parameter by name, SI units.

        Raises
        ------
        InsErrorsError
            For an unknown ellipsoid or parameter, a model without Earth-shape parameters,
            a non-finite value, a value given that no model could take (a negative
            damping gain, an Earth radius that is not positive, an eccentricity squared
            outside [0, 1): :func:`~ins_errors.model_parameters.parameter_problem`, as
            for values read from text), or a value outside the model's own parameter
            domain (the same check and message as a run's).
        """
        from ins_errors.models.earth import ellipsoid as lookup

        values = {i.name: float(i.default) for i in self.parameters}
        if ellipsoid is not None:
            shape = lookup(ellipsoid)
            for axis, eccentricity in (("a", "e2"), ("R", "ecc2")):
                if axis in values and eccentricity in values:
                    values[axis] = shape.semi_major_axis
                    values[eccentricity] = shape.eccentricity_squared
                    break
            else:
                raise InsErrorsError(f"model {self.name!r} has no Earth-shape parameters to "
                                     f"set from ellipsoid {ellipsoid!r}")
        from ins_errors.model_parameters import parameter_problem

        problems = []
        for key, value in overrides.items():
            info = self.parameters[self.index("parameters", key)]
            values[key] = self._number(value, info, "parameter_vector")
            problem = parameter_problem(self, info, values[key])
            if problem is not None:
                problems.append(f"parameter_vector: {key} = {values[key]:g}: {problem}")
        p = np.array([values[i.name] for i in self.parameters])
        self._check_finite(p, "parameters")
        self._parameter_domain(p, f"parameters of {self.name}")  # the model's own words first
        if problems:
            raise InsErrorsError(problems[0])
        return p

    def source_vector(self, **magnitudes: float) -> np.ndarray:
        """Error-source vector ``w`` (SI), zero except the named sources.

        Raises
        ------
        InsErrorsError
            For an unknown source or a magnitude that is not a finite number;
            :class:`~ins_errors.errors.DomainError` for one beyond what a run can mean
            (:func:`~ins_errors.model_parameters.source_problem`: an angle beyond one
            turn, a drift beyond 1 rad/s, ...).
        """
        from ins_errors.model_parameters import source_problem

        w = np.zeros(len(self.sources))
        for key, value in magnitudes.items():
            k = self.index("sources", key)
            w[k] = self._number(value, self.sources[k], "source_vector")
        self._check_finite(w, "error sources")
        for key in magnitudes:
            k = self.index("sources", key)
            problem = source_problem(self.sources[k], w[k])
            if problem is not None:
                raise DomainError(f"source_vector: {key} = {w[k]:g} "
                                     f"{self.sources[k].unit} {problem}")
        return w

    def input_vector(self, **values: float) -> np.ndarray:
        """Input vector ``u`` (SI), zero except the named inputs."""
        u = np.zeros(len(self.inputs))
        for key, value in values.items():
            k = self.index("inputs", key)
            u[k] = self._number(value, self.inputs[k], "input_vector")
        self._check_finite(u, "inputs")
        return u

    def initial_condition_vector(self, **values: float) -> np.ndarray:
        """Initial-condition vector ``c`` (SI: radians, m/s), zero except those named."""
        c = np.zeros(len(self.initial_conditions))
        for key, value in values.items():
            k = self.index("initial_conditions", key)
            c[k] = self._number(value, self.initial_conditions[k], "initial_condition_vector")
        self._check_finite(c, "initial conditions")
        return c

    # -- validation ---------------------------------------------------------------------
    @staticmethod
    def _number(value: Any, info: Info, function: str) -> float:
        """One real number in SI units, or a one-line error naming the quantity."""
        return si_number(value, f"{function}: {info.name}", info.unit)

    @staticmethod
    def _check_finite(array: np.ndarray, what: str) -> None:
        bad = ~np.isfinite(array)
        if bad.any():
            position = tuple(int(i[0]) for i in np.nonzero(bad))
            raise DomainError(f"{what} {_verb(what)} NaN or infinite values (first at index "
                              f"{position if len(position) > 1 else position[0]})")

    def _vector(self, value: Any, infos: tuple[Info, ...], what: str, function: str) -> np.ndarray:
        if np.iscomplexobj(value):
            raise ShapeError(f"{function}: {what} must be real, got complex values")
        if np.ma.isMaskedArray(value) and np.ma.getmaskarray(value).any():
            # np.asarray would drop the mask and evaluate the hidden values as if valid
            position = tuple(int(i[0]) for i in np.nonzero(np.ma.getmaskarray(value)))
            raise ShapeError(f"{function}: {what} has masked entries (first at index "
                             f"{position if len(position) > 1 else position[0]}): fill or "
                             "drop them first (numpy.ma's filled, compressed)")
        try:
            array = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise ShapeError(f"{function}: {what} must be numeric, got {value!r:.60}") from None
        n = len(infos)
        if array.ndim == 0 or array.shape[0] != n:
            raise ShapeError(f"{function}: {what} must have shape ({n}, ...) "
                             f"[{', '.join(i.name for i in infos)}], got {array.shape}")
        self._check_finite(array, f"{function}: {what}")
        return array

    @staticmethod
    def _batch(function: str, **arrays: np.ndarray) -> None:
        """Refuse arguments whose trailing batch axes do not broadcast together."""
        shapes = [a.shape[1:] for a in arrays.values()]
        try:
            np.broadcast_shapes(*shapes)
        except ValueError:
            listing = ", ".join(f"{name} {shape}" for name, shape in zip(arrays, shapes,
                                                                         strict=True))
            raise ShapeError(f"{function}: the batch axes (after the first) of the arguments "
                             f"do not match: {listing}") from None

    @staticmethod
    def _latitudes(array: np.ndarray, rows: tuple[int, ...], infos: tuple[Info, ...],
                   function: str) -> None:
        """Refuse a latitude beyond ±90° (the model's own check refuses ±90° itself)."""
        for k in rows:
            if np.any(np.abs(array[k]) > np.pi / 2):
                worst = float(np.max(np.abs(array[k])))
                raise DomainError(f"{function}: {infos[k].name} must be within ±90° "
                                  f"(±π/2 rad), got |{infos[k].name}| = "
                                  f"{np.degrees(worst):.6g}°")

    def _domain(self, margins: np.ndarray, messages: tuple[str, ...], function: str,
                explain: Callable[[int, str, np.ndarray], str | None] | None = None) -> None:
        """Refuse the first condition whose margins are not all > 0, one line; ``explain``
        (condition index, message, mask of the failing points) may give a better line."""
        margins = np.asarray(margins)
        for k, message in enumerate(messages):
            failed = ~(margins[k] > 0)
            if failed.any():
                line = explain(k, message, failed) if explain is not None else None
                raise DomainError(f"{function}: {line or message}")

    def _check_state(self, x, u, p, function: str):
        x = self._vector(x, self.states, "state x", function)
        u = self._vector(u, self.inputs, "inputs u", function)
        p = self.parameter_vector() if p is None else self._vector(
            p, self.parameters, "parameters p", function)
        self._batch(function, x=x, u=u, p=p)
        self._latitudes(x, self._state_latitudes, self.states, function)
        self._domain(self.numpy.domain_margins(x, u, p), self.meta.DOMAIN, function)
        return x, u, p

    # -- evaluators (validated) -----------------------------------------------------------
    def ideal_rhs(self, x, u, p=None) -> np.ndarray:
        """Ideal-work ``dx/dt``, shape ``(n, ...)``."""
        return self.numpy.ideal_rhs(*self._check_state(x, u, p, "ideal_rhs"))

    def real_rhs(self, xr, x, u, w, p=None) -> np.ndarray:
        """Real-work ``dxr/dt``, shape ``(ne, ...)``."""
        x, u, p = self._check_state(x, u, p, "real_rhs")
        xr = self._vector(xr, self._real_states, "real state xr", "real_rhs")
        w = self._vector(w, self.sources, "error sources w", "real_rhs")
        self._batch("real_rhs", xr=xr, x=x, u=u, w=w, p=p)
        self._domain(self.numpy.domain_margins(xr[: len(self.states)], u, p),
                     self.meta.DOMAIN, "real_rhs (computed state)")
        return self.numpy.real_rhs(xr, x, u, w, p)

    def outputs_of(self, x, u, p=None) -> np.ndarray:
        """Navigation outputs of a state, shape ``(ny, ...)``."""
        return self.numpy.outputs(*self._check_state(x, u, p, "outputs"))

    def state_matrix(self, x, u, p=None) -> np.ndarray:
        """F of ``ẋe = F xe + G w`` at the ideal state ``x`` (shape ``(n, ...)``), inputs
        ``u`` ``(nu, ...)`` and parameters ``p`` ``(np,)`` or ``(np, ...)`` (default: the
        model's defaults, :meth:`parameter_vector`), all SI; shape ``(ne, ne, ...)``:
        rows and columns follow :attr:`error_states` (entry (i, j) in the SI unit of
        state i per second per unit of state j), batch axes last. The batch axes of
        ``x``, ``u`` and ``p`` broadcast against each other: ``p`` of shape ``(np, B)``
        at one state gives ``(ne, ne, B)``, F for B parameter sets."""
        return self.numpy.state_matrix(*self._check_state(x, u, p, "state_matrix"))

    def source_matrix(self, x, u, p=None) -> np.ndarray:
        """G, shape ``(ne, nw, ...)``: rows follow :attr:`error_states`, columns
        :attr:`sources` (each in its SI unit); arguments as :meth:`state_matrix`."""
        return self.numpy.source_matrix(*self._check_state(x, u, p, "source_matrix"))

    def output_matrix(self, x, u, p=None) -> np.ndarray:
        """H of ``ye = H xe``, shape ``(ny, ne, ...)``: rows follow :attr:`outputs`,
        columns :attr:`error_states`; arguments as :meth:`state_matrix`."""
        return self.numpy.output_matrix(*self._check_state(x, u, p, "output_matrix"))

    def second_order(self, x, u, xe, w, p=None) -> np.ndarray:
        """Second-order term of the error equations, shape ``(ne, ...)``."""
        x, u, p = self._check_state(x, u, p, "second_order")
        xe = self._vector(xe, self.error_states, "error state xe", "second_order")
        w = self._vector(w, self.sources, "error sources w", "second_order")
        self._batch("second_order", x=x, u=u, xe=xe, w=w, p=p)
        return self.numpy.second_order(x, u, p, xe, w)

    def run_parameters(self, p: Any, function: str) -> np.ndarray:
        """Check the parameter vector of a whole run (one value each, no batch axes).

        Parameters
        ----------
        p : array_like of shape (np,) or None
            Parameters, SI; None: the model's defaults.
        function : str
            Name of the calling function, for the messages.

        Returns
        -------
        numpy.ndarray, shape (np,)

        Raises
        ------
        ShapeError, DomainError
            Another shape, NaN or infinite values, or a value outside the model's own
            parameter domain (e.g. an eccentricity squared of 1 or more).
        """
        if p is None:
            return self.parameter_vector()
        p = self._vector(p, self.parameters, "parameters p", function)
        if p.ndim != 1:
            raise ShapeError(f"{function}: parameters p must have shape ({len(self.parameters)},)"
                             f" [{', '.join(i.name for i in self.parameters)}], got {p.shape}")
        self._parameter_domain(p, f"{function}: parameters p")
        return p

    def _parameter_domain(self, p: np.ndarray, where: str) -> None:
        """Refuse parameters (shape (np,)) outside the model's own domain, one line
        starting with ``where``."""
        # the initial conditions and inputs at zero (equator, at rest, level) are inside
        # every domain: a margin that fails there is the parameters' own
        margins = self.numpy.initial_domain_margins(
            np.zeros(len(self.initial_conditions)), np.zeros(len(self.inputs)), p)
        self._domain(margins, self.meta.INITIAL_DOMAIN, where)

    def _check_initial(self, c, u, p, function: str):
        c = self._vector(c, self.initial_conditions, "initial conditions c", function)
        u = self._vector(u, self.inputs, "inputs u", function)
        p = self.parameter_vector() if p is None else self._vector(
            p, self.parameters, "parameters p", function)
        self._batch(function, c=c, u=u, p=p)
        self._latitudes(c, self._initial_latitudes, self.initial_conditions, function)
        self._initial_domain(c, u, p, function)
        return c, u, p

    def _initial_domain(self, c: np.ndarray, u: np.ndarray, p: np.ndarray,
                        function: str) -> None:
        """The initial-condition domain check; a latitude too close to a pole is named
        with its value and the model's distance of singularity (:meth:`_pole_line`)."""
        def at_the_first_failure(k: int, message: str, failed: np.ndarray) -> str | None:
            batch = np.broadcast_shapes(c.shape[1:], u.shape[1:], p.shape[1:])
            at = (slice(None), *np.argwhere(np.broadcast_to(failed, batch))[0])
            # batch axes align on the right (numpy broadcasting): an argument with fewer
            # batch axes (e.g. one parameter vector of shape (np,)) gets leading ones
            first = [np.broadcast_to(a.reshape(a.shape[0], *(1,) * (len(batch) - a.ndim + 1),
                                               *a.shape[1:]), (a.shape[0], *batch))[at]
                     for a in (c, u, p)]
            return self._pole_line(k, message, *first)

        self._domain(self.numpy.initial_domain_margins(c, u, p), self.meta.INITIAL_DOMAIN,
                     function, at_the_first_failure)

    def _pole_line(self, k: int, message: str, c: np.ndarray, u: np.ndarray,
                   p: np.ndarray) -> str | None:
        """The line for initial-domain condition ``k`` failing at one point (c, u, p of
        shape (nc,), (nu,), (np,)) because a latitude is too close to a pole, else None.

        The condition is a pole's when it holds with that latitude moved to the equator;
        the latitude where it stops holding is then found by bisection (the model's own
        margin, at the point's other values), so the line quotes the model's actual
        tolerance: e.g. ``cos²φ > 1e-12`` is singular within 1e-6 rad (0.206″) of a pole.
        """
        def holds(row: int, latitude: float) -> bool:
            moved = c.copy()
            moved[row] = latitude
            return bool(np.asarray(self.numpy.initial_domain_margins(moved, u, p))[k] > 0)

        for row in self._initial_latitudes:
            given = float(c[row])
            if not holds(row, 0.0) or holds(row, given):
                continue
            inside, outside = 0.0, abs(given)  # |latitude| where it holds / fails
            for _ in range(200):
                middle = 0.5 * (inside + outside)
                if middle in (inside, outside):
                    break
                if holds(row, np.copysign(middle, given)):
                    inside = middle
                else:
                    outside = middle
            tolerance = np.pi / 2 - inside
            if tolerance >= np.radians(1.0):
                within = f"{np.degrees(tolerance):.3g}°"
            else:
                within = f"{np.degrees(tolerance) * 3600:.3g}″ ({tolerance:.3g} rad)"
            reason = message.split(": ", 1)[-1]
            return (f"{self.initial_conditions[row].name} {np.degrees(given):.10g}° is "
                    f"refused: the {self.name} model's formulas are singular within "
                    f"{within} of a pole; {reason}")
        return None

    def check_start_latitude(self, latitude: float, p: np.ndarray, function: str) -> None:
        """Refuse a motion's start latitude where the model's initial conditions do not
        hold (near a pole), before anything is computed from it.

        Parameters
        ----------
        latitude : float
            Start latitude, rad.
        p : numpy.ndarray, shape (np,)
            Parameters, SI (already checked).
        function : str
            Name of the calling function, for the message.

        Raises
        ------
        DomainError
            One line with the latitude and the model's distance of singularity from the
            pole (e.g. 0.206″ for a model that needs cos²φ > 1e-12).
        """
        c = np.zeros(len(self.initial_conditions))
        c[list(self._initial_latitudes)] = latitude
        # the other initial conditions and the inputs at zero lie inside every domain
        self._initial_domain(c, np.zeros(len(self.inputs)), np.asarray(p, dtype=float),
                             function)

    def initial_state(self, c, u, p=None) -> np.ndarray:
        """True initial state from initial conditions, shape ``(n, ...)``."""
        return self.numpy.initial_state(*self._check_initial(c, u, p, "initial_state"))

    def initial_real_state(self, c, u, w, p=None) -> np.ndarray:
        """Real-work initial state (initial-error sources applied), shape ``(ne, ...)``."""
        c, u, p = self._check_initial(c, u, p, "initial_real_state")
        w = self._vector(w, self.sources, "error sources w", "initial_real_state")
        self._batch("initial_real_state", c=c, u=u, w=w, p=p)
        return self.numpy.initial_real_state(c, u, w, p)

    def initial_error_matrix(self, c, u, p=None) -> np.ndarray:
        """E with ``xe(0) = E w`` to first order, shape ``(ne, nw, ...)``."""
        return self.numpy.initial_error_matrix(*self._check_initial(c, u, p,
                                                                    "initial_error_matrix"))
