"""Names a model file gives its quantities, and what the tools show of them.

* a state and an initial condition (or any two of states, error states, inputs,
  parameters, error sources, initial conditions) with one name would be one SymPy
  symbol: refused in one line with a name to use instead; outputs may share names;
* moving motions take the initial velocities as ``v_N``/``v_E`` or ``v_N0``/``v_E0``;
* ``models FILE`` shows every parameter's default with its unit;
* the words about platforms (α the platform misalignment, the manual's factor numbers,
  the platform kinematics of a run) appear only for models that have them.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

from ins_errors import load_model
from ins_errors.cli import main
from ins_errors.numeric import trajectories as tr

ROOT = Path(__file__).resolve().parent.parent
MODELS = Path(__file__).resolve().parent / "models"
STRAPDOWN_FILE = ROOT / "examples" / "strapdown" / "strapdown_sphere.py"
STRAPDOWN = STRAPDOWN_FILE.read_text(encoding="utf-8")


@pytest.fixture
def private_cache(tmp_path, monkeypatch):
    """A cache of the test's own for its throw-away model files (the fixture and example
    files' code stays in the user's cache, derived once, as the documented commands keep
    it)."""
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))


@pytest.mark.usefixtures("private_cache")
def test_a_state_and_an_initial_condition_of_one_name_are_refused(tmp_path, capsys):
    """The researcher's file named the initial east velocity v_E, like the state: the
    listing then printed the state as v_{E0}."""
    path = tmp_path / "clash.py"
    path.write_text(STRAPDOWN.replace('"v_E0"', '"v_E"'), encoding="utf-8")
    assert main(["models", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    assert "state 'v_E' and initial condition 'v_E'" in err and "'v_E0'" in err, err


@pytest.mark.usefixtures("private_cache")
def test_a_state_named_like_a_flights_initial_condition_is_the_one_to_rename(tmp_path,
                                                                              capsys):
    """An Euler-angle model's state 'roll' beside the initial condition 'roll': the
    message suggested renaming the initial condition to 'roll0', which every run then
    refuses (flights and the static base set 'roll' by that name alone)."""
    from ins_errors.numeric.model_flight import CONDITIONS
    from ins_errors.symbolic.consistency import FILLED_BY_NAME

    # the names flights fill with no '0' alias are those the message protects
    assert {n for n in CONDITIONS if not n.startswith("v_")} == FILLED_BY_NAME
    assert all(f"{n}0" in CONDITIONS for n in CONDITIONS if n.startswith("v_")
               and not n.endswith("0"))
    path = tmp_path / "clash.py"
    source = (MODELS / "euler_angle_ins.py").read_text(encoding="utf-8")
    clash = source.replace('Variable("phi", "rad", "roll angle"',
                           'Variable("roll", "rad", "roll angle"')
    assert clash != source
    path.write_text(clash, encoding="utf-8")
    assert main(["models", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    assert "e.g. the state to 'roll_state'" in err and "'roll0'" not in err, err


@pytest.mark.usefixtures("private_cache")
def test_an_input_named_like_a_parameter_is_refused(tmp_path, capsys):
    path = tmp_path / "clash.py"
    path.write_text(STRAPDOWN.replace('"g"', '"f_z"'), encoding="utf-8")
    assert main(["models", str(path)]) == 2
    err = capsys.readouterr().err
    assert "parameter 'f_z' and input 'f_z'" in err and "the input to 'f_z_in'" in err, err


def test_initial_velocities_named_v_N0_v_E0_follow_a_moving_motion():
    """A motion file's east velocity of 100 m/s along the equator: the true longitude
    advances by v t / R (refused before: 'no east velocity (initial condition v_E)')."""
    model = load_model(str(MODELS / "velocity_sphere.py"))
    R = model.parameter_vector()[0]
    t = np.linspace(0.0, 2000.0, 21)
    profile = tr.sampled_profile(t, np.zeros_like(t), np.full_like(t, 100.0), 0.0, 0.0, 0.0)
    traj = tr.trajectory(model, profile, 1000.0, 10.0)
    assert traj.truth[3, -1] == pytest.approx(100.0 * 1000.0 / R, rel=1e-9)
    np.testing.assert_allclose(traj.truth[:2, -1], [0.0, 100.0], atol=1e-9)
    assert list(traj.initial_conditions) == [0.0, 0.0, 0.0, 100.0]


def test_models_lists_parameter_defaults(capsys):
    """The defaults stated in the fixture file (R = 6 371 000 m, g = 9.81 m/s²)."""
    assert main(["models", str(STRAPDOWN_FILE)]) == 0
    text = capsys.readouterr().out
    rows = {line.split()[0]: line for line in text.split("parameters:")[1].split("\n\n")[0]
            .strip().splitlines()}
    assert rows["R"].endswith("(default 6371000 m)")
    assert rows["g"].endswith("(default 9.81 m/s^2)")
    assert main(["models", str(STRAPDOWN_FILE), "--json"]) == 0
    listed = {p["name"]: p for p in json.loads(capsys.readouterr().out)["parameters"]}
    assert (listed["g"]["default"], listed["g"]["unit"]) == (9.81, "m/s**2")


def test_models_names_the_damping_gains_with_their_examples(capsys):
    """strapdown_ned flags k_h1, k_h2 as damping gains with example values: the listing
    says so (what the growth warning would suggest), and only for them."""
    assert main(["models", "strapdown_ned"]) == 0
    text = capsys.readouterr().out
    rows = {line.split()[0]: line for line in text.split("parameters:")[1].split("\n\n")[0]
            .strip().splitlines()}
    assert rows["k_h1"].endswith("(default 0/s; a damping gain, e.g. -p k_h1=0.0293/s (a "
                                 "300-s loop, damping 0.7))")
    assert "damping gain" in rows["k_h2"]
    assert not any("damping gain" in row for name, row in rows.items()
                   if name not in ("k_h1", "k_h2"))


def test_platform_words_only_for_platform_models():
    generated = ROOT / "generated"
    text = {name: (generated / name / "error_equations.md").read_text(encoding="utf-8")
            for name in ("orthodromic", "north_pointing", "strapdown_ned")}
    assert "α the platform misalignment" in text["orthodromic"]
    assert "α the platform misalignment" in text["north_pointing"]
    assert "platform misalignment" not in text["strapdown_ned"]
    # the source document's factor numbers: only the orthodromic model has them
    assert "manual factor" in text["orthodromic"]
    assert "manual factor" not in text["north_pointing"]
    assert "manual factor" not in text["strapdown_ned"]


def test_extra_error_states_are_named_by_their_own_meaning():
    """A model file's extra state that is not a platform angle (the tutorial's tilt ψ)."""
    from ins_errors.model_lookup import definition_of, resolve
    from ins_errors.symbolic.documents import _extra_states

    definition = definition_of(resolve(str(ROOT / "examples/own_model/schuler_loop.py")))
    assert _extra_states(definition) == r", $\psi$ the platform tilt about the west axis"


def test_report_platform_row_only_with_a_choice_of_platform():
    from ins_errors.report import has_platform_variants

    assert has_platform_variants(load_model("orthodromic"))
    assert not has_platform_variants(load_model("strapdown_ned"))


def test_a_damping_loops_integrators_are_named_with_the_extra_states():
    """The tangent-plane INS's integrators q_E, q_N (m/s², no platform angles) are named
    in the introduction of its error equations beside its platform angles."""
    from ins_errors.model_lookup import definition_of, resolve
    from ins_errors.symbolic.documents import _extra_states

    definition = definition_of(resolve(str(ROOT / "tests/models/tangent_plane_ins.py")))
    text = _extra_states(definition)
    named = [v.name for v in definition.extra_error_states]
    assert {"q_E", "q_N"} <= set(named)
    assert all(f"${v.latex}$" in text for v in definition.extra_error_states)


def test_modelling_choices_read_as_markdown_without_docstring_roles():
    """A model's notes are its docstring (reStructuredText): a cross-reference role was
    shown literally in error_equations.md and every report ('... rotation,
    :mod:`ins_errors.models.platform`)'); it is the code span of its target."""
    from ins_errors.symbolic.documents import markdown_text

    assert markdown_text("exact rotation, :mod:`ins_errors.models.platform`); "
                         ":func:`~x.levelling_offsets` ``R_N``") == (
        "exact rotation, `ins_errors.models.platform`); `x.levelling_offsets` ``R_N``")
    for document in sorted((ROOT / "generated").glob("*/error_equations.md")):
        text = document.read_text(encoding="utf-8")
        assert not re.search(r":(mod|func|class|data|meth|attr):`", text), document
