"""A model file whose real work reads a true state where the computer has its own.

The computer integrates its computed state; reading the true ``lat`` where ``lat_c``
belongs (a one-character slip) still reduces to the ideal work and derives, but the error
of the computed latitude then never feeds back where the formula uses it. It is refused
in one line naming the equation or intermediate, the true state and the computed one;
what a model reads on purpose (an external reference, a platform's true rotation, a
sensor on a tilted platform) stays silent or is declared with ``reads_true_state``.
"""

from __future__ import annotations

import glob
from pathlib import Path

import pytest

from ins_errors.cli import main
from tests.helpers import fresh_model_cache

ROOT = Path(__file__).resolve().parent.parent
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"
SPHERE = ROOT / "examples" / "strapdown" / "strapdown_sphere.py"
SCHULER_ROWS = "real_rhs = sp.Matrix([f, omega_c, omega_c - omega + drift])"


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    return fresh_model_cache(tmp_path, monkeypatch)


def copy_with(source: Path, tmp_path: Path, *replacements: tuple[str, str]) -> Path:
    """``source`` copied into ``tmp_path`` with text replacements."""
    text = source.read_text(encoding="utf-8")
    for old, new in replacements:
        assert old in text, old
        text = text.replace(old, new)
    target = tmp_path / "my_ins.py"
    target.write_text(text, encoding="utf-8")
    return target


def refusal(path: Path, capsys) -> str:
    """The one line ``ins-errors derive`` refuses ``path`` with (exit status 2)."""
    out = path.parent / "out"
    status = main(["derive", str(path), "--out", str(out)])
    captured = capsys.readouterr()
    assert status == 2, captured.err
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("ins-errors: error: "), captured.err
    assert not out.exists()
    return lines[0]


def test_latitude_rate_from_the_true_velocity_is_refused(tmp_path, capsys):
    # dφ~/dt = V/R (the true V) where the computer has V~: the latitude error would no
    # longer follow the velocity error (the Schuler loop opens); other rows read V_c
    path = copy_with(SCHULER, tmp_path,
                     (SCHULER_ROWS, SCHULER_ROWS.replace("[f, omega_c,", "[f, V / R,")))
    line = refusal(path, capsys)
    for words in ("real-work equation (real_rhs) for 'delta_phi'", "true state V",
                  "the computer has V_c", "write V_c", "reads_true_state=['V']",
                  "(step: checking the definition)"):
        assert words in line, (words, line)
    assert "more" not in line  # one place only


def test_the_ideal_works_intermediate_in_the_real_work_is_refused(tmp_path, capsys):
    # omega (the ideal work's V/R) where omega_c (the commanded V~/R) belongs
    path = copy_with(SCHULER, tmp_path,
                     (SCHULER_ROWS, SCHULER_ROWS.replace("[f, omega_c,", "[f, omega,")))
    line = refusal(path, capsys)
    for words in ("'delta_phi'", "through the ideal-work intermediate omega",
                  "true state V", "write the real work's omega_c in place of the ideal "
                  "work's omega"):
        assert words in line, (words, line)


def test_strapdown_navigator_fed_the_true_latitude_is_refused(tmp_path, capsys):
    # the ENU probe's slip: the real work's navigator gets the true lat among x~
    path = copy_with(SPHERE, tmp_path,
                     ("navigator(real, x_c, gyros, accels)",
                      "navigator(real, [*x_c[:12], x[12], *x_c[13:]], gyros, accels)"))
    line = refusal(path, capsys)
    for words in ("real-work intermediate Omega_N_c", "true state lat",
                  "the computer has lat_c", "write lat_c", "more equation(s)"):
        assert words in line, (words, line)


def test_a_declared_true_state_read_is_derived(tmp_path, capsys):
    # dead reckoning on a log: the latitude integrates the log's (true) velocity on
    # purpose; declared, the file derives, and δφ then does not follow δV
    path = copy_with(SCHULER, tmp_path,
                     (SCHULER_ROWS, SCHULER_ROWS.replace("[f, omega_c,", "[f, V / R,")),
                     ('        name="schuler_loop",',
                      '        name="schuler_loop",\n        reads_true_state=["V"],'))
    assert main(["derive", str(path), "--out", str(tmp_path / "out")]) == 0, \
        capsys.readouterr().err
    from ins_errors.model_files import load_model_file
    from ins_errors.symbolic.variation import vary

    d = load_model_file(path)
    F = vary(d).state_matrix
    row = [v.name for v in d.error_states].index("delta_phi")
    assert list(F.row(row)) == [0, 0, 0]  # the true V: no error of V~ reaches φ~


@pytest.mark.parametrize("declared, words", [
    ('["lat"]', "reads_true_state: 'lat' is not a state; the states are V, phi"),
    ('"V"', "reads_true_state: must be a list of state names"),
])
def test_a_wrong_declaration_is_one_line(declared, words, tmp_path, capsys):
    path = copy_with(SCHULER, tmp_path,
                     ('        name="schuler_loop",',
                      f'        name="schuler_loop",\n        reads_true_state={declared},'))
    assert words in refusal(path, capsys)


def test_no_shipped_model_reads_a_true_state_by_mistake():
    # every built-in, test and example model reads the truth only on purpose: the
    # platforms' true rotation, sensors on a tilted platform, external references
    from ins_errors.model_files import load_model_file
    from ins_errors.models import definition, model_names
    from ins_errors.symbolic.true_state_reads import true_state_reads

    for name in model_names():
        assert true_state_reads(definition(name)) == [], name
    files = [*sorted(glob.glob(str(ROOT / "tests" / "models" / "*.py"))),
             *sorted(glob.glob(str(ROOT / "examples" / "**" / "*.py"), recursive=True))]
    checked = 0
    for file in files:
        if "def build(" in Path(file).read_text(encoding="utf-8"):
            load_model_file(Path(file))  # the check runs here: refused would raise
            checked += 1
    assert checked >= 15


def test_make_derive_refuses_a_built_in_model_edited_into_the_same_slip(tmp_path,
                                                                       monkeypatch):
    """`python -m derive` (make derive) builds the built-in models through its own
    pipeline, not through a model file's loader: the same check runs there."""
    import importlib.util

    from derive import pipeline
    from ins_errors.errors import ModelDefinitionError

    path = copy_with(SCHULER, tmp_path,
                     (SCHULER_ROWS, SCHULER_ROWS.replace("[f, omega_c,", "[f, V / R,")))
    spec = importlib.util.spec_from_file_location("slipped_loop", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    monkeypatch.setattr(pipeline, "definition", lambda name: module.build())
    with pytest.raises(ModelDefinitionError, match=r"reads the true state V"):
        pipeline._write_one("north_pointing", tmp_path / "generated", documents=False)
