r"""The public authoring API of ins-errors: write an INS model as SymPy, once.

A model is one Python file (or module) with a function ``build()`` that returns a
:class:`ModelDefinition`. The built-in models (``ins_errors/models/*.py``) are written with
exactly the names of this module; a researcher's own file needs nothing else.

API at a glance
---------------
Names (public, stable, with SI units and LaTeX):

* :class:`Variable`: a state, input, output or initial condition;
* :class:`Parameter`: a model constant with its default value (a damping-loop gain is
  flagged ``damping_gain=True``, with an ``example`` value to suggest);
* :class:`ErrorSource` / :func:`error_source`: an instrument or initial error (``kind``
  ``"constant"`` enters the right-hand side, ``"initial"`` only the initial state);
* :func:`error_states_of`: the error-state names ``delta_<state>`` plus extra ones
  (platform angles);
* :func:`computed_symbols`: the symbols ``<state>_c`` of the on-board (real-work) state.

Equations:

* :class:`Mechanisation`: records named intermediate quantities with :meth:`Mechanisation.let`
  the way a paper writes ``R_E = ...``; one for the ideal work, one (``computed=True``)
  for the real work;
* :class:`ModelDefinition`: everything together: ideal and real right-hand sides, the
  output map, initial states, document groups, notes and domain checks.

Earth (re-exported from :mod:`ins_errors.models.earth`, the one home of these formulas):
:data:`EARTH_RATE`, :data:`ELLIPSOIDS`, :class:`Ellipsoid`, :func:`ellipsoid`,
:func:`radii_of_curvature`, :func:`normal_gravity` (numpy or SymPy arguments) and the
WGS-84 gravity constants.

Gyro-stabilised platform (re-exported from :mod:`ins_errors.models.platform`):
:func:`on_platform` resolves a vector on the misaligned platform, :func:`platform_rates`
advances the platform angles, each ``"exact"`` (rotation) or ``"small_angle"`` (the
source documents' matrix); a platform model builds both and passes the small-angle
real-work equations as ``ModelDefinition.small_angle_rhs``.

The vocabulary the machinery relies on:

* the ideal-work state ``x`` has ``n`` components; the real-work state ``x~`` starts with
  the computed counterparts of ``x`` (same order, symbols ``<name>_c``) and continues with
  quantities that are zero in ideal work (platform misalignment angles);
* the error state is ``x~ - (x, 0)``; its linearisation ``d(xe)/dt = F xe + G w`` and the
  output errors ``H xe`` are derived mechanically (:mod:`ins_errors.symbolic.variation`).

Rules a definition must follow (checked, with a one-line error naming the quantity, by
:func:`ins_errors.symbolic.consistency.check_definition` before a model file is derived):
symbols come from the declared names (``Variable.symbol``, real-valued; a bare
``sp.Symbol("g")`` is a different symbol), and no two states, error states, inputs,
parameters, error sources or initial conditions share a name (one name is one symbol: name
the initial east velocity ``v_E0`` when a state is ``v_E``; outputs may share); every
right-hand side has one row per state; every symbol an equation uses is declared (or
recorded with ``let``); functions are SymPy's; an error source's kind is ``"constant"`` or
``"initial"`` and its display unit converts to its SI unit; every declared unit is
coherent SI (``"rad/s"``, not ``"deg/h"``); parameter defaults are finite;
each right-hand side has the unit of its state per second
(:func:`~ins_errors.symbolic.consistency.check_dimensions`); and with the computed state on
the true one and every error source zero, the real work gives the ideal derivatives and zero
for the extra states (else the error equations would have a forcing that no error source
explains).

A complete small model, written step by step, is the tutorial
``examples/own_model/schuler_loop.py`` (a single-axis Schuler loop); the built-in
``ins_errors/models/north_pointing.py`` is a full platform INS in the same style.

Run ``ins-errors derive my_ins.py --out DIR`` to write the generated package, or give
the file wherever a command takes a model name (``ins-errors models ./my_ins.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

import sympy as sp

from ins_errors.errors import ModelDefinitionError
from ins_errors.models.earth import (
    EARTH_RATE,
    ELLIPSOIDS,
    MEAN_RADIUS,
    STANDARD_GRAVITY,
    WGS84_EQUATORIAL_GRAVITY,
    WGS84_GRAVITY_M,
    WGS84_SOMIGLIANA_K,
    Ellipsoid,
    ellipsoid,
    normal_gravity,
    radii_of_curvature,
)
from ins_errors.models.platform import PLATFORM_FORMS, on_platform, platform_rates
from ins_errors.symbolic.shared_trees import SharedTrees

__all__ = [
    "EARTH_RATE",
    "ELLIPSOIDS",
    "MEAN_RADIUS",
    "MODE_NOTE_KEYS",
    "PLATFORM_FORMS",
    "STANDARD_GRAVITY",
    "WGS84_EQUATORIAL_GRAVITY",
    "WGS84_GRAVITY_M",
    "WGS84_SOMIGLIANA_K",
    "Definition",
    "Ellipsoid",
    "ErrorSource",
    "Mechanisation",
    "ModelDefinition",
    "ModelDefinitionError",
    "Parameter",
    "Variable",
    "accent",
    "computed_symbols",
    "ellipsoid",
    "error_source",
    "error_states_of",
    "normal_gravity",
    "on_platform",
    "platform_rates",
    "radii_of_curvature",
    "tilde",
]


@dataclass(frozen=True)
class Variable:
    """A named scalar of a model (state, input, parameter, output, initial condition).

    Attributes
    ----------
    name : str
        Public identifier (stable API), a valid Python identifier.
    unit : str
        Coherent SI unit, in a form the units library parses (``"rad"``, ``"m/s"``,
        ``"1"``): every value of a model is taken as SI, so a unit whose scale to SI is
        not 1 (``"deg/h"``, ``"km"``, ``"%"``) is refused when a model file is checked
        (an error source keeps ``"deg/h"`` as its display unit).
    description : str
        One-line meaning.
    latex : str
        LaTeX spelling used in generated documents.
    """

    name: str
    unit: str
    description: str
    latex: str

    @property
    def symbol(self) -> sp.Symbol:
        """The SymPy symbol of this variable (real-valued)."""
        return sp.Symbol(self.name, real=True)


@dataclass(frozen=True)
class Parameter(Variable):
    """A model constant (Earth shape, Earth rate, tuning radius, loop gain) with its
    default value.

    Attributes
    ----------
    default : float
        Value used when a run does not override it, in ``unit`` (SI).
    damping_gain : bool
        True for a gain of a damping loop, whose 0 leaves the loop open (``strapdown_ned``'s
        vertical-channel gains ``k_h1``, ``k_h2``): when the error equations grow
        exponentially, the warning names the flagged gains that are 0 and how to set them.
    example : str
        A value to suggest, with its unit as typed after ``-p NAME=`` (``"0.0293/s"``);
        empty: none. Read by the units library when a model file is checked.
    example_gives : str
        What the example values give, a short phrase (``"a 300-s loop, damping 0.7"``);
        empty: nothing said. Only with an ``example``.

    Examples
    --------
    >>> gain = Parameter("k_1", "1/s", "height loop gain", "k_1", 0.0, damping_gain=True,
    ...                  example="0.0293/s", example_gives="a 300-s loop, damping 0.7")
    """

    default: float = 0.0
    damping_gain: bool = False
    example: str = ""
    example_gives: str = ""


@dataclass(frozen=True)
class ErrorSource(Variable):
    """One error source of the real-work equations.

    Attributes
    ----------
    kind : {"constant", "initial"}
        ``"constant"`` sources enter the real-work right-hand side (they form the matrix
        G); ``"initial"`` sources only change the real system's initial state.
    display_unit : str
        Engineering unit people quote the source in (``"deg/h"``, ``"ug"``, ``"arcsec"``).
    factor : int or None
        Number of the matching factor in the list of the source document's lab task 1,
        where there is one.
    """

    kind: Literal["constant", "initial"] = "constant"
    display_unit: str = ""
    factor: int | None = None


def error_source(name: str, unit: str, display_unit: str, kind: str, factor: int | None,
                 latex: str, description: str) -> ErrorSource:
    """An :class:`ErrorSource` in the compact positional form the model catalogues use.

    Parameters
    ----------
    name : str
        Public identifier, e.g. ``"gyro_drift_east"``.
    unit : str
        SI unit (``"rad/s"``, ``"m/s**2"``, ``"rad"``).
    display_unit : str
        Unit people quote it in (``"deg/h"``, ``"ug"``, ``"arcmin"``); scenario files and
        reports use it.
    kind : {"constant", "initial"}
        ``"constant"``: enters the real-work right-hand side (a column of G);
        ``"initial"``: only changes the real-work initial state.
    factor : int or None
        Factor number of the source document's lab task 1, or None.
    latex : str
        LaTeX symbol, e.g. ``r"\varepsilon_E"``.
    description : str
        One-line meaning.

    Returns
    -------
    ErrorSource
    """
    return ErrorSource(name, unit, description, latex, kind=kind, display_unit=display_unit,
                       factor=factor)


def error_states_of(states: Sequence[Variable], extra: Sequence[Variable]) -> tuple[Variable, ...]:
    """Error-state names: ``delta_<state>`` for each computed state, then ``extra``.

    Parameters
    ----------
    states : sequence of Variable
        The ideal-work states, in order.
    extra : sequence of Variable
        Real-work states that are zero in ideal work (platform angles), in order.

    Returns
    -------
    tuple of Variable
        ``len(states) + len(extra)`` error states, units of the states they belong to.
    """
    return (
        *(Variable(f"delta_{v.name}", v.unit, f"error of the computed {v.description}",
                   rf"\Delta {v.latex}") for v in states),
        *extra,
    )


def computed_symbols(states: Sequence[Variable]) -> list[sp.Symbol]:
    """Symbols of the on-board (computed, "tilde") counterparts of ``states``.

    The real-work state of a :class:`ModelDefinition` starts with these symbols,
    ``<name>_c``, in the order of ``states``; a :class:`Mechanisation` with
    ``computed=True`` names its intermediates the same way.

    Parameters
    ----------
    states : sequence of Variable
        The ideal-work states.

    Returns
    -------
    list of sympy.Symbol
        One real symbol per state.
    """
    return [sp.Symbol(f"{v.name}_c", real=True) for v in states]


@dataclass(frozen=True)
class Definition:
    """One named intermediate quantity ``symbol = expression`` of a mechanisation."""

    symbol: sp.Symbol
    expression: sp.Expr
    latex: str


@dataclass
class Mechanisation:
    """Records the named intermediate quantities of one set of work equations.

    Use :meth:`let` the way a paper writes ``R_E = ...``: it returns a symbol that later
    formulas use, and remembers the definition so that the chain of formulas can be
    printed, varied term by term, or expanded into closed expressions.

    Parameters
    ----------
    computed : bool
        True for the real-work (on-board, "tilde") quantities; their symbols get the
        suffix ``_c`` and their LaTeX a tilde.
    """

    computed: bool = False
    definitions: list[Definition] = field(default_factory=list)

    def let(self, name: str, expression: sp.Expr, latex: str) -> sp.Symbol:
        """Define a named intermediate quantity and return its symbol.

        Parameters
        ----------
        name : str
            Identifier of the quantity (``"r_E"``); ``_c`` is appended in a computed
            mechanisation.
        expression : sympy.Expr
            Its formula, in states, inputs, parameters, sources and earlier symbols.
        latex : str
            LaTeX spelling for documents (a tilde is added in a computed mechanisation).

        Returns
        -------
        sympy.Symbol
            The symbol standing for the quantity in later formulas.

        Raises
        ------
        ModelDefinitionError
            If ``name`` is defined twice in this mechanisation.
        """
        symbol = sp.Symbol(f"{name}_c" if self.computed else name, real=True)
        if any(d.symbol == symbol for d in self.definitions):
            raise ModelDefinitionError(f"intermediate {symbol} defined twice")
        shown = tilde(latex) if self.computed else latex
        self.definitions.append(Definition(symbol, sp.sympify(expression), shown))
        return symbol

    def expand(self, expression: sp.Expr | sp.Matrix) -> sp.Expr | sp.Matrix:
        """Substitute every recorded definition, innermost last, into ``expression``.

        Each substitution is ``xreplace`` (the same result) through one
        :class:`~ins_errors.symbolic.shared_trees.SharedTrees`, which rebuilds each
        distinct subtree once: the substituted formulas repeat their subtrees many times.
        """
        trees = SharedTrees()
        for definition in reversed(self.definitions):
            rule = {definition.symbol: definition.expression}
            if isinstance(expression, sp.MatrixBase):
                expression = trees.xreplace_matrix(expression, rule)
            elif isinstance(expression, sp.Basic):
                expression = trees.xreplace(expression, rule)
            else:
                expression = expression.xreplace(rule)
        return expression


def accent(latex: str, mark: str) -> str:
    r"""Put an accent on the base of a LaTeX name: ``accent("V_\xi", "tilde")``.

    A leading ``\Delta`` stays in front (``\Delta\dot{V}_\xi``).
    """
    prefix = ""
    if latex.startswith("\\Delta "):
        prefix, latex = "\\Delta", latex[len("\\Delta "):]
    head, sep, tail = latex.partition("_")
    if head.startswith("{") or not head:
        return rf"{prefix}\{mark}{{{latex}}}"
    return rf"{prefix}\{mark}{{{head}}}{sep}{tail}"


def tilde(latex: str) -> str:
    r"""LaTeX of the computed ("tilde") version of a quantity, e.g. ``\tilde{V}_\xi``."""
    return accent(latex, "tilde")


MODE_NOTE_KEYS = ("Schuler", "Earth", "vertical channel")
"""The named static-base modes a :attr:`ModelDefinition.mode_notes` entry may explain:
``"Schuler"`` (also "Schuler − Foucault" and "Schuler + Foucault"), ``"Earth"``,
``"vertical channel"`` (growing and decaying)."""


@dataclass
class ModelDefinition:
    """The complete symbolic definition of one INS, as the variation machinery needs it.

    The ideal-work state ``x`` (true navigation quantities) has ``n`` components; the
    real-work state ``x~`` starts with the computed counterparts of ``x`` (same order)
    and continues with quantities that are zero in ideal work (platform misalignment
    angles). The error state is ``x~ - (x, 0)``.

    Attributes
    ----------
    name, title, source : str
        Registry name, human title, source document reference.
    states : sequence of Variable
        Ideal-work state ``x``.
    error_states : sequence of Variable
        Names of the error-state components (``delta_...`` and the platform angles).
    real_states : sequence of sympy.Symbol
        Symbols of the real-work state ``x~`` (same length as ``error_states``).
    inputs : sequence of Variable
        True-motion inputs ``u`` (apparent accelerations, vertical channel).
    parameters : sequence of Parameter
        Model constants ``p``.
    sources : sequence of ErrorSource
        Error sources ``w``.
    outputs : sequence of Variable
        Navigation outputs ``y``.
    initial_conditions : sequence of Variable
        Navigation data the run starts from (``c``: latitude, longitude, ...).
    ideal : Mechanisation
        Intermediate definitions of the ideal-work equations.
    real : Mechanisation
        Intermediate definitions of the real-work equations (may reference ideal ones).
    ideal_rhs : sympy.Matrix
        ``dx/dt`` of the ideal work, in states, inputs, parameters and ``ideal`` symbols.
    real_rhs : sympy.Matrix
        ``dx~/dt`` of the real work, in real states, true states, inputs, sources,
        parameters and intermediate symbols of both mechanisations (the truth of a
        direct run: exact platform kinematics).
    small_angle_rhs : sympy.Matrix or None
        The same with the source documents' small-angle platform (selectable in direct
        runs as ``platform="small_angle"``); None for a model without that variant. Its
        first-order variation must equal that of ``real_rhs``.
    output_map : callable
        ``output_map(mechanisation, state_symbols, input_symbols)`` -> Matrix of the
        outputs in terms of the given state symbols (called with the ideal state for
        true outputs and the computed state for indicated outputs).
    initial_state : sympy.Matrix
        ``x(0)`` in initial conditions, inputs and parameters.
    initial_real_state : sympy.Matrix
        ``x~(0)`` in initial conditions, inputs, sources and parameters.
    groups : sequence of (str, list of str)
        How the error equations are grouped in documents (title, error-state names).
    notes : str
        Markdown paragraph on modelling choices, printed at the top of generated docs.
    domain : sequence of (sympy.Expr, str)
        Conditions ``expr > 0`` in ``x, u, p`` where the formulas hold, with the one-line
        message given when one fails (e.g. latitude at a pole).
    initial_domain : sequence of (sympy.Expr, str)
        The same for the initial conditions, in ``c, u, p``.
    mode_notes : mapping of str to str
        Why a static-base mode of this model is not at its textbook value, when that is
        a property of the mechanisation (``ins-errors modes`` prints the note beside the
        mode): keys from :data:`MODE_NOTE_KEYS` (``"Schuler"`` covers the Foucault-split
        pair too), values one paragraph of plain text.
    reads_true_state : sequence of str
        Names of states whose true value the real work reads on purpose where the
        computer also has the computed one: an external reference (a log or GNSS
        velocity the computer is damped by or integrates) or what a sensor senses.
        Without it, a real-work equation of a computed state (or a real intermediate
        that the ideal work defines too) that reads the true state and not its computed
        counterpart is refused (:mod:`ins_errors.symbolic.true_state_reads`).
    """

    name: str
    title: str
    source: str
    states: Sequence[Variable]
    error_states: Sequence[Variable]
    real_states: Sequence[sp.Symbol]
    inputs: Sequence[Variable]
    parameters: Sequence[Parameter]
    sources: Sequence[ErrorSource]
    outputs: Sequence[Variable]
    initial_conditions: Sequence[Variable]
    ideal: Mechanisation
    real: Mechanisation
    ideal_rhs: sp.Matrix
    real_rhs: sp.Matrix
    output_map: Callable[..., sp.Matrix]
    initial_state: sp.Matrix
    initial_real_state: sp.Matrix
    small_angle_rhs: sp.Matrix | None = None
    groups: Sequence[tuple[str, list[str]]] = ()
    notes: str = ""
    domain: Sequence[tuple[sp.Expr, str]] = ()
    initial_domain: Sequence[tuple[sp.Expr, str]] = ()
    mode_notes: Mapping[str, str] = field(default_factory=dict)
    reads_true_state: Sequence[str] = ()

    def __post_init__(self) -> None:
        unknown = sorted(set(self.mode_notes) - set(MODE_NOTE_KEYS))
        if unknown:
            raise ModelDefinitionError(f"model {self.name!r}: mode_notes has no mode "
                                 f"{', '.join(map(repr, unknown))}; known: "
                                 f"{', '.join(MODE_NOTE_KEYS)}")

    # -- platform -------------------------------------------------------------------
    @property
    def extra_error_states(self) -> tuple[Variable, ...]:
        """The error states beyond ``delta_<state>`` of the computed states: the real-work
        states that are zero in ideal work (platform angles, and any other such state, e.g.
        a damping loop's integrator in m/s²); empty for a strapdown INS."""
        return tuple(self.error_states[len(self.states):])

    @property
    def platform_angles(self) -> tuple[Variable, ...]:
        """The platform misalignment angles: the :attr:`extra_error_states` in rad (a
        real-work state of another unit, such as an integrator, is no attitude); empty for
        a strapdown INS. The one rule of which error states are platform angles."""
        return tuple(v for v in self.extra_error_states if v.unit == "rad")

    @property
    def has_small_angle_platform(self) -> bool:
        """True for a model whose platform kinematics a direct run chooses (the exact
        rotation or the source documents' small-angle matrix, ``small_angle_rhs``): the
        three-axis platforms of the source documents, whose angles they call α. Derive
        generates ``real_rhs_small_angle`` exactly for these
        (:attr:`ins_errors.numeric.model.Model.has_small_angle_platform`)."""
        return self.small_angle_rhs is not None

    # -- symbol vectors -------------------------------------------------------------
    @property
    def x(self) -> list[sp.Symbol]:
        """Ideal-work state symbols."""
        return [v.symbol for v in self.states]

    @property
    def u(self) -> list[sp.Symbol]:
        """Input symbols."""
        return [v.symbol for v in self.inputs]

    @property
    def p(self) -> list[sp.Symbol]:
        """Parameter symbols."""
        return [v.symbol for v in self.parameters]

    @property
    def w(self) -> list[sp.Symbol]:
        """Error-source symbols."""
        return [v.symbol for v in self.sources]

    @property
    def c(self) -> list[sp.Symbol]:
        """Initial-condition symbols."""
        return [v.symbol for v in self.initial_conditions]

    @property
    def xe(self) -> list[sp.Symbol]:
        """Error-state symbols (used by the second-order term)."""
        return [v.symbol for v in self.error_states]

    # -- expanded (closed-form) equations ---------------------------------------------
    def expand(self, expression: sp.Matrix) -> sp.Matrix:
        """Substitute the real, then the ideal, intermediate definitions."""
        return self.ideal.expand(self.real.expand(expression))

    def ideal_rhs_expanded(self) -> sp.Matrix:
        """``dx/dt`` in states, inputs and parameters only."""
        return self.ideal.expand(self.ideal_rhs)

    def real_rhs_expanded(self) -> sp.Matrix:
        """``dx~/dt`` in real states, true states, inputs, sources and parameters only."""
        return self.expand(self.real_rhs)

    def outputs_expanded(self) -> sp.Matrix:
        """Outputs of the ideal state, in states, inputs and parameters only."""
        scratch = Mechanisation()
        outputs = scratch.expand(self.output_map(scratch, self.x, self.u))
        return outputs if outputs.rows else sp.zeros(0, 1)  # no outputs: sp.Matrix([])

    def at_ideal(self) -> dict[sp.Symbol, sp.Expr]:
        """Substitution taking the real state to the ideal point ``x~ = (x, 0)``."""
        n = len(self.states)
        point: dict[sp.Symbol, sp.Expr] = dict(zip(self.real_states[:n], self.x, strict=True))
        point.update({s: sp.S.Zero for s in self.real_states[n:]})
        return point

    def no_errors(self) -> dict[sp.Symbol, sp.Expr]:
        """Substitution switching every error source off."""
        return {s: sp.S.Zero for s in self.w}

    def latex_names(self) -> dict[sp.Symbol, str]:
        """LaTeX spelling of every symbol the model uses."""
        names: dict[sp.Symbol, str] = {}
        for group in (self.states, self.inputs, self.parameters, self.sources,
                      self.outputs, self.initial_conditions):
            names.update({v.symbol: v.latex for v in group})
        names.update({v.symbol: v.latex for v in self.error_states})
        n = len(self.states)
        for sym, var in zip(self.real_states[:n], self.states, strict=True):
            names[sym] = tilde(var.latex)
        for mech in (self.ideal, self.real):
            names.update({d.symbol: d.latex for d in mech.definitions})
        return names
