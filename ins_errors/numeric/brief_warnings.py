"""The terminal's short form of the integration-error warnings.

The full warning (kept in :attr:`~ins_errors.numeric.compare.Comparison.warnings`, the
report and the JSON) names the quantity furthest past its limit, its integration error,
its largest error, the limit and why, the step that would bring it under, the largest
share of any quantity and the refined run's own estimate: some 900 characters. The
terminal prints one or two lines instead (:func:`~ins_errors.numeric.compare.markdown_summary`
with ``brief=True``): what is wrong, how big, and the cure that makes sense. A rectangle
step that would take more than :data:`STEPS` steps for the run is not advised there (a
day at τ = 1 ms is 86 million steps): the line says the rectangle method cannot get
there in a sensible run and RK4 can, with RK4's own step when it was estimated. One
that is tiny (:data:`SHRINK`) comes after RK4.
"""

from __future__ import annotations

from dataclasses import dataclass

STEPS = 10_000_000
"""Steps for the run beyond which the short warning advises no rectangle-method step
(about 10 s of CPU per run of the built-in models, and the check runs it again at other
steps): RK4 instead."""

SHRINK = 100
"""A rectangle step this many times shorter than the run's, or one of more than a tenth
of :data:`STEPS` steps, is named after RK4, not as the cure."""

RK4_SHORT = '--method rk4, or method = "rk4" in [run]'
"""How the short warning tells a command line and a scenario file to use RK4."""


def step_count(count: float) -> str:
    """``"86.4 million"``, ``"1.61 billion"``, ``"52,000"``: a number of steps in words."""
    if count >= 1e9:
        return f"{count / 1e9:.3g} billion"
    if count >= 1e6:
        return f"{count / 1e6:.3g} million"
    return f"{count:,.0f}"


def times(factor: float) -> str:
    """``"698 times"``, ``"2.3 times"``, ``"1,320 times"``: how far past its limit."""
    return f"{factor:,.0f} times" if factor >= 100 else f"{factor:.2g} times"


def _size(quantity: str, share: str, over: float, tenth: bool, model: str) -> str:
    """``"alpha_y's is 4.21% of its error, 70 times its linear − direct difference"``:
    how big, against what the comparison measures (the limit is a tenth of that
    difference, or 1 % of the error when the difference is at rounding)."""
    if not tenth:
        return f"{quantity}'s is {share} of its error (limit 1%)"
    against = (f"{times(over / 10)} its" if over >= 10 else "over a tenth of its")
    return f"{quantity}'s is {share} of its error, {against} {model} − direct difference"


def _cannot(needed: float, duration: float, rk4_text: str | None) -> str:
    """The advice when the rectangle method would need more than :data:`STEPS` steps."""
    at = f", at τ = {rk4_text} s" if rk4_text else ""
    return (f"the rectangle method cannot get there in a sensible run "
            f"({step_count(duration / needed)} steps), RK4 can ({RK4_SHORT}{at})")


@dataclass
class Integration:
    """What the short integration-error warning says (filled as the full one is built).

    Attributes
    ----------
    tau : float
        The run's step, s.
    scheme : str
        ``"rectangle method"`` or ``"RK4"``.
    duration : float
        The run's length, s.
    step : float
        The step the full warning names for the scheme (s), before any RK4 advice.
    needed : float
        The step (s) the estimate asks for, before it is made one the command line
        takes (``step`` is at or below it).
    text : str
        That step as it is typed.
    rk4_text : str or None
        RK4's own step (typed) when it was estimated.
    order, scheme_order : float or None, int
        Observed order of the estimate and the scheme's.
    failed : str or None
        Why the run that measures the order failed.
    unreliable : bool
        The estimate is outside its asymptotic range.
    worst : tuple or None
        (quantity, its share of its error as text, integration error / limit, whether
        the limit is a tenth of the linear − direct difference) of the quantity furthest
        past its limit; None when none is past it.
    refined_too : bool
        The refined run's integration error is over its limit too.
    """

    tau: float
    scheme: str
    duration: float
    step: float
    needed: float
    text: str
    rk4_text: str | None
    order: float | None
    scheme_order: int
    failed: str | None
    unreliable: bool = False
    worst: tuple[str, str, float, bool] | None = None
    refined_too: bool = False

    def line(self) -> str:
        """The short warning, one or two terminal lines."""
        if self.unreliable:
            how = (self.failed.split(":")[0] if self.failed is not None else
                   f"observed order {self.order:.2g}, scheme order {self.scheme_order}")
            head = (f"integration error not reliable at τ = {self.tau:g} s, {self.scheme} "
                    f"({how})")
        else:
            head = f"integration error too large at τ = {self.tau:g} s, {self.scheme}"
        size = f": {_size(*self.worst, 'linear')}" if self.worst is not None else ""
        goal = "bring it under" if self.worst is not None else "make the estimate reliable"
        if self.scheme == "rectangle method" and self.duration / self.needed > STEPS:
            advice = _cannot(self.needed, self.duration, self.rk4_text)
        elif self.scheme == "rectangle method" and (
                self.tau / self.needed > SHRINK or self.duration / self.needed > STEPS / 10):
            advice = (f"RK4 ({RK4_SHORT}) would {goal} in far fewer steps than the "
                      f"rectangle method's τ = {self.text} s "
                      f"({step_count(self.duration / self.step)} steps)")
        elif self.scheme == "rectangle method":
            advice = (f"τ = {self.text} s would {goal}, or RK4 ({RK4_SHORT}) in far fewer "
                      "steps")
        else:
            advice = f"τ = {self.text} s would {goal}"
        refined = ("; the refined run's integration error is over its limit too"
                   if self.refined_too else "")
        return f"{head}{size}; {advice}{refined}"


def refined_alone(tau: float, scheme: str, duration: float, needed: float, quantity: str,
                  share: str, over: float, tenth: bool) -> str:
    """The short warning on the refined run's integration error said alone (the linear
    pair's is under its limit).

    Parameters
    ----------
    tau, duration, needed : float
        The run's step, its length and about the step that would bring the estimate
        under its limit, s.
    scheme : str
        ``"rectangle method"`` or ``"RK4"``.
    quantity, share, over, tenth
        As :attr:`Integration.worst`, for the direct and refined runs.
    """
    if scheme == "rectangle method" and duration / needed > STEPS:
        advice = _cannot(needed, duration, None)
    else:
        advice = f"about τ ≤ {needed:.3g} s would bring it under"
    return (f"the refined run's integration error is too large at τ = {tau:g} s, {scheme}: "
            f"{_size(quantity, share, over, tenth, 'refined')}; {advice}")
