"""How a researcher's symbols map to a model's names (the hand checker's notation).

A hand-written derivation uses its own symbols: the lab manual of source 000 writes
radii ``R_ξ`` where the model uses reciprocals ``1/R_ξ``, one accelerometer error ``Δa``
for both channels, one drift ``ω_dp`` for all three gyros, the Earth-rate components
``U_ξ = U u11``, and direction cosines ``u13, u23`` the model never integrates. A
:class:`Notation` says what each such symbol means in model terms:

* ``aliases``: hand name -> expression in the model's names (ideal quantities). The
  variation of an alias follows by the chain rule, so ``Delta_R_eta`` means
  ``-Delta_inv_R_eta / inv_R_eta**2`` without any extra entry.
* ``sources``: hand error-source symbol -> the model's error sources it stands for; on the
  model side every listed source is set equal to the hand symbol (``Delta_a`` is
  ``accel_bias_x`` in the ξ channel and ``accel_bias_y`` in the η channel).
* ``spellings``: alternative ASCII spellings -> the canonical one (``w_xi`` ->
  ``omega_xi``, ``lambda`` -> ``lam``).
* ``latex_primes``: what a prime means on a LaTeX base letter (``\\omega'`` is the
  relative rate ``omega_rel``, ``g'`` the gravitation projection ``g``).

A mapping file (``@alias`` / ``@source`` lines, see ``docs/hand_check.md``) adds to or
overrides the model's default notation.
"""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass
class Notation:
    """Symbol mapping between a hand derivation and a model (see module docstring)."""

    aliases: dict[str, str] = field(default_factory=dict)
    sources: dict[str, tuple[str, ...]] = field(default_factory=dict)
    spellings: dict[str, str] = field(default_factory=dict)
    latex_primes: dict[str, str] = field(default_factory=dict)

    def merged(self, other: Notation) -> Notation:
        """This notation with ``other``'s entries added (``other`` wins on conflicts)."""
        return Notation(
            aliases={**self.aliases, **other.aliases},
            sources={**self.sources, **other.sources},
            spellings={**self.spellings, **other.spellings},
            latex_primes={**self.latex_primes, **other.latex_primes},
        )


_AXES = ("xi", "eta", "zeta")


def _rate_spellings() -> dict[str, str]:
    """``w_xi``, ``omega_xi_rel``, ``w_rel_xi``, ... -> ``omega_xi`` / ``omega_rel_xi``."""
    spellings: dict[str, str] = {}
    for axis in _AXES:
        spellings[f"w_{axis}"] = f"omega_{axis}"
        for spelling in (f"omega_{axis}_rel", f"w_{axis}_rel", f"w_rel_{axis}",
                         f"omega_{axis}_p", f"omegap_{axis}"):
            spellings[spelling] = f"omega_rel_{axis}"
    for axis in ("N", "E"):
        spellings[f"w_{axis}"] = f"omega_{axis}"
    return spellings


ORTHODROMIC = Notation(
    aliases={
        # radii of curvature: the model keeps their reciprocals
        "R_xi": "1/inv_R_xi",
        "R_eta": "1/inv_R_eta",
        "R_o": "1/inv_R_o",
        # Earth-rate components along the trihedron (u_ξ, u_η, u_ζ of the manual)
        "U_xi": "U*u11",
        "U_eta": "U*u21",
        "U_zeta": "U*u31",
        # the direction cosines obtained from cross products (u33 is a model name)
        "u13": "u21*u32 - u22*u31",
        "u23": "u31*u12 - u11*u32",
        # eccentricity (the manual writes e^2)
        "e": "sqrt(e2)",
    },
    sources={
        "Delta_a": ("accel_bias_x", "accel_bias_y"),
        "omega_dp": ("gyro_drift_x", "gyro_drift_y", "gyro_drift_z"),
    },
    spellings={
        "lambda": "lam",
        "varphi": "phi",
        "W_xi_nk": "W_xi",
        "W_eta_nk": "W_eta",
        "g_p_xi": "g_xi",
        "g_p_eta": "g_eta",
        "u_xi": "U_xi",
        "u_eta": "U_eta",
        "u_zeta": "U_zeta",
        "w_dp": "omega_dp",
        **_rate_spellings(),
    },
    latex_primes={"omega": "omega_rel", "g": "g"},
)

NOTATIONS: dict[str, Notation] = {"orthodromic": ORTHODROMIC}
"""Default notation of each model's source document (models without one get none)."""


def default_notation(model: str) -> Notation:
    """The default notation of ``model`` (an empty one if the model has none)."""
    return NOTATIONS.get(model, Notation())
