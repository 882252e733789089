"""Every subcommand a script may drive offers --json, and its output parses."""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parent.parent

COMMANDS = {
    "models": ["models", "orthodromic", "--json"],
    "compare": ["compare", "orthodromic", "--source", "gyro_drift_y=0.01deg/h", "--hours", "1",
                "--no-refined", "--json", "--no-progress"],
    "budget": ["budget", "orthodromic", "--json"],
    "check": ["check", "orthodromic", str(ROOT / "examples/manual_000/equations.txt"), "--json"],
    "study": ["study", "nonsphericity", "--hours", "1", "--scenario", "static", "--json"],
    "propagation": ["propagation", "--hours", "1", "--json"],
    "cache": ["cache", "info", "--json"],
}


def strict_json(text: str):
    """``text`` parsed as strict JSON: NaN / Infinity / -Infinity refused (JavaScript's
    JSON.parse and jq refuse them; Python's json.loads takes them by default)."""
    def refuse(constant):
        raise ValueError(f"not JSON: {constant}")

    return json.loads(text, parse_constant=refuse)


@pytest.mark.parametrize("name", COMMANDS)
def test_json_output_parses(name, capsys):
    status = main(COMMANDS[name])
    # check exits 1: the manual's printed equations have mistakes; the others find nothing
    assert status == (1 if name == "check" else 0)
    data = strict_json(capsys.readouterr().out)
    assert data


def test_strict_parser_refuses_nan():
    with pytest.raises(ValueError, match="NaN"):
        strict_json('{"a": NaN}')


def test_overflowing_matrix_check_writes_strict_json(tmp_path, monkeypatch, capsys):
    """g instead of g/R in F[4, 7] of the ψ model: a mode growing with an e-folding time
    under a second overflows the 24 h propagation. The JSON says null (and exponential),
    never NaN, and no floating-point warning reaches the user."""
    source = (ROOT / "examples/strapdown/psi_model.py").read_text(encoding="utf-8")
    marker = "    G = np.zeros((9, 6))\n"
    assert marker in source
    (tmp_path / "hm.py").write_text(source.replace(marker, "    F[4, 7] = 9.81\n" + marker),
                                    encoding="utf-8")
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "cache"))  # propagate afresh
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        status = main(["check", "strapdown_ned", "--matrix", f"{tmp_path / 'hm.py'}:psi_model",
                       "--convention", "psi", "--json"])
    captured = capsys.readouterr()
    assert status == 1
    assert "Warning" not in captured.err
    data = strict_json(captured.out)
    [wrong] = [f for f in data["findings"] if (f["row"], f["column"]) == ("dvc_E", "dr_E")]
    alone = wrong["effect_alone_24h"]
    assert alone["exponential"] and alone["position_m"] is None
    # 9.81 /s² coupling of a position into a velocity: e-folding 1/sqrt(9.81) s
    assert alone["e_folding_s"] == pytest.approx(9.81 ** -0.5, rel=0.05)


def test_json_writer_turns_non_finite_numbers_into_null():
    import numpy as np

    from ins_errors.json_output import dumps

    text = dumps({"a": float("nan"), "b": [np.float64(np.inf), np.array([1.0, -np.inf])],
                  "c": np.int64(3), "d": (np.bool_(True), None)})
    assert strict_json(text) == {"a": None, "b": [None, [1.0, None]], "c": 3,
                                 "d": [True, None]}


def test_every_subcommand_has_help(capsys):
    from ins_errors.cli import build_parser

    parser = build_parser()
    commands = parser._subparsers._group_actions[0].choices
    assert set(COMMANDS) | {"run"} <= set(commands)
    for name, sub in commands.items():
        text = sub.format_help()
        assert len(sub.description or "") > 40, name
        assert "--json" in text, name


def test_check_summary_has_one_schema_whatever_is_found(tmp_path, capsys):
    """Every status key is always there (0 when none), keys are snake_case, and the
    equations counted by status are kept apart from the findings counted by class."""
    from tests.test_hand_check import CORRECT

    good = tmp_path / "good.txt"
    good.write_text(CORRECT)
    assert main(["check", "orthodromic", str(good), "--json"]) == 0
    clean = strict_json(capsys.readouterr().out)
    assert main(COMMANDS["check"]) == 1
    manual = strict_json(capsys.readouterr().out)

    def keys(tree, prefix=""):
        return {prefix + k for k in tree} | {
            key for k, v in tree.items() if isinstance(v, dict) for key in keys(v, k + ".")}

    assert keys(clean["summary"]) == keys(manual["summary"])
    assert all(k.replace(".", "_").replace("_", "").isalnum() and k == k.lower()
               for k in keys(manual["summary"]))
    statuses = {"agrees", "agrees_up_to_dropped_small_terms", "agrees_up_to_declared_drops",
                "mistake", "hand_only_definition", "tautology", "input_error"}
    for data in (clean, manual):
        summary = data["summary"]
        by_status = summary["equations_by_status"]
        assert set(by_status) == statuses
        # counted from the equations and their findings, independently of the summary
        for status in statuses:
            assert by_status[status] == sum(
                1 for e in data["equations"]
                if e["status"].replace("-", "_").replace(" ", "_") == status), status
        # classes "mistake" and "mistake, small effect" are both mistakes
        mistakes = [f for e in data["equations"] for f in e["findings"]
                    if f["class"].startswith("mistake")]
        assert summary["findings"]["mistakes"] == len(mistakes)
        assert summary["findings"]["root_mistakes"] == sum(f["role"] == "root" for f in mistakes)
        assert summary["input_problems"] == len(data["problems"])
    assert clean["summary"]["equations_by_status"]["mistake"] == 0
    assert manual["summary"]["equations_by_status"]["mistake"] > 0


def test_list_conventions_json_matches_the_text(capsys):
    assert main(["check", "strapdown_ned", "--list-conventions"]) == 0
    text = capsys.readouterr().out
    assert main(["check", "strapdown_ned", "--list-conventions", "--json"]) == 0
    data = strict_json(capsys.readouterr().out)
    assert data["model"] == "strapdown_ned"
    headers = [line.split(":")[0] for line in text.splitlines() if not line.startswith(" ")]
    assert [c["name"] for c in data["conventions"]] + ["bias states"] == headers
    # the error sources that may be bias states: the constant ones, listed alike
    assert [b["name"] for b in data["bias_states"]][:3] == ["gyro_bias_x", "gyro_bias_y",
                                                           "gyro_bias_z"]
    assert "initial_roll_error" not in {b["name"] for b in data["bias_states"]}
    for bias in data["bias_states"]:
        assert f"  {bias['name']} ({bias['unit']}): " in text
    psi = next(c for c in data["conventions"] if c["name"] == "psi")
    assert len(psi["states"]) == 9  # ψ, δv, δr in NED, as examples/strapdown/psi_model.py
    for state in psi["states"]:
        assert f"  {state['name']} ({state['unit']}): " in text


def test_study_list_json(capsys):
    from ins_errors.commands.study import study_names

    assert main(["study", "list", "--json"]) == 0
    rows = strict_json(capsys.readouterr().out)
    assert [r["name"] for r in rows] == study_names()
    assert all(r["description"] for r in rows)


def test_write_samples_json_describes_the_file(tmp_path, monkeypatch, capsys):
    import numpy as np

    monkeypatch.chdir(tmp_path)
    assert main(["check", "strapdown_ned", "--write-samples", "x.npz", "--json"]) == 0
    data = strict_json(capsys.readouterr().out)
    stored = np.load(tmp_path / "x.npz")
    assert data["samples"] == "x.npz" and data["motions"]
    for motion in data["motions"]:
        t = stored[f"t_{motion['label']}"]
        assert motion["samples"] == t.size
        assert (motion["start_s"], motion["stop_s"]) == (t[0], t[-1])


def test_study_json_has_the_maxima_as_numbers(capsys):
    """The direct and linear maxima of the text are in the JSON as SI numbers, with the
    mismatch ratio under its own name and compare's excited flag; a quantity the text
    calls "not excited" is flagged so, whatever its ratio."""
    import math

    assert main(["study", "coriolis", "--hours", "2", "--scenario", "static", "--json"]) == 0
    (run,) = strict_json(capsys.readouterr().out)["runs"]
    assert "agreement" not in run
    arcsec = 180 / math.pi * 3600
    for line in run["lines"][2:]:
        words = line.split()
        if words[0] not in ("alpha_x", "alpha_y"):
            continue
        q = run["quantities"][words[0]]
        assert q["unit"] == "rad"
        assert float(words[2]) == pytest.approx(q["direct_max_rad"] * arcsec, rel=1e-3)
        assert float(words[4]) == pytest.approx(q["linear_max_rad"] * arcsec, rel=1e-3)
    for name, q in run["quantities"].items():
        suffix = "m_per_s" if q["unit"] == "m/s" else q["unit"].replace("/", "_per_")
        direct, difference = q[f"direct_max_{suffix}"], q[f"difference_max_{suffix}"]
        if direct > 0:
            assert q["mismatch_ratio"] == pytest.approx(difference / direct), name
        shown = [line for line in run["lines"] if line.split()[:1] == [name]]
        if shown:
            assert ("not excited" in shown[0]) == (not q["excited"]
                                                   and not q["at_rounding_level"]), name
    # on a static base nothing turns the platform about the vertical: α_z is not excited
    assert run["quantities"]["alpha_z"]["excited"] is False


def test_spheroid_study_json_has_the_table(spheroid_study_hour):
    status, out = spheroid_study_hour  # study spheroid --hours 1 --json
    assert status == 0
    data = strict_json(out)
    flights = data["flights"]
    table = [line.split() for line in data["lines"]
             if len(line.split()) == 6 and line.split()[0].replace(".", "").isdigit()]
    assert len(flights) == len(table) == 16
    for row, flight in zip(table, flights, strict=True):
        assert float(row[0]) == pytest.approx(math_degrees(flight["start_latitude_rad"]),
                                              abs=0.05)
        assert float(row[2]) == pytest.approx(flight["geometric_max_m"] / 1000, abs=5e-4)
        assert float(row[3]) == pytest.approx(flight["mismatch_completed_max_m"] / 1000,
                                              abs=5e-4)
        # over an hour at 250 m/s the displacement cannot exceed the distance flown
        assert 0 < flight["geometric_max_m"] < 250 * 3600


def math_degrees(radians: float) -> float:
    import math

    return math.degrees(radians)


def test_the_listed_attitude_sign_is_the_one_the_maps_use(capsys):
    """--list-conventions states φ's sign, C̃_b^n = (I − [φ×]) C_b^n: a computed attitude
    made that way from a known φ reads back as +φ through the convention's map (the sign
    is stated where a filter designer looks, and it is the one the numbers use)."""
    from scipy.spatial.transform import Rotation

    from ins_errors import load_model
    from ins_errors.models import strapdown_conventions as sc

    assert main(["check", "strapdown_ned", "--list-conventions"]) == 0
    listing = capsys.readouterr().out
    phi_line = next(line for line in listing.splitlines() if line.startswith("phi:"))
    assert "C̃_b^n = (I − [φ×]) C_b^n" in phi_line and "ṽ − v" in phi_line
    model = load_model("strapdown_ned")
    p = model.parameter_vector()
    c = model.initial_condition_vector(latitude=np.radians(40), roll=0.1, pitch=-0.2,
                                       heading=1.0)
    x = model.initial_state(c, model.input_vector(), p)
    phi = np.array([2e-6, -3e-6, 5e-6])
    C = Rotation.from_quat(np.roll(x[:4], -1)).as_matrix()  # scalar-first → scipy's order
    skew = np.array([[0, -phi[2], phi[1]], [phi[2], 0, -phi[0]], [-phi[1], phi[0], 0]])
    q = np.roll(Rotation.from_matrix((np.eye(3) - skew) @ C).as_quat(), 1)
    q *= np.sign(q @ x[:4])
    e = np.zeros(10)
    e[:4] = q - x[:4]
    got = sc.transform_matrix("phi", x[:, None], p)[..., 0] @ e
    np.testing.assert_allclose(got[:3], phi, rtol=1e-4)
