"""F that is 0/0 at a point (a drag c|V|V at rest: d|V|/dV has no value at V = 0) is
refused by every command that evaluates it there in one line naming the entries, with
no numpy warning about the generated code before it (modes, transfer, matrices and the
Python API's error_matrices; compare and run: tests/test_compare_probe_fixes.py)."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest

from ins_errors import InsErrorsError, load_model
from ins_errors.cli import main
from ins_errors.conventions import error_matrices

DRAG_MODEL = str(Path(__file__).resolve().parent / "models" / "velocity_drag.py")
ENTRIES = ("F[delta_V_N, delta_V_N], F[delta_V_N, delta_V_E], F[delta_V_E, delta_V_N] "
           "and F[delta_V_E, delta_V_E]")


def _drag_derivative(v: np.ndarray, c: float = 1e-3) -> np.ndarray:
    """∂(−c|V|V)/∂V by hand: −c (|V| I + V Vᵀ/|V|), finite off V = 0."""
    speed = np.linalg.norm(v)
    return -c * (speed * np.eye(2) + np.outer(v, v) / speed)


@pytest.mark.parametrize("command", [["modes"], ["transfer"],
                                     ["matrices", "--out", "{tmp}/m.npz"]])
def test_a_command_at_rest_names_the_entries_and_prints_no_numpy_warning(command, tmp_path,
                                                                         capsys):
    argv = [command[0], DRAG_MODEL, *(a.format(tmp=tmp_path) for a in command[1:])]
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        assert main(argv) == 2
    assert [str(w.message) for w in seen if issubclass(w.category, RuntimeWarning)] == []
    [line] = [text for text in capsys.readouterr().err.splitlines() if " error: " in text]
    assert ENTRIES in line and "d|V|/dV at V = 0" in line


def test_the_api_names_the_entries_and_is_finite_off_rest():
    model = load_model(DRAG_MODEL)
    p = model.parameter_vector()
    u = np.zeros((2, 2))
    with warnings.catch_warnings(record=True) as seen:
        warnings.simplefilter("always")
        with pytest.raises(InsErrorsError, match=r"at sample 1 \(of 2\) in F\[delta_V_N"):
            error_matrices(model, "model", np.array([[3.0, 0.0], [-4.0, 0.0]]), u, p)
    assert not [w for w in seen if issubclass(w.category, RuntimeWarning)]
    # off rest the same F is the hand derivative of the drag (the refusal is V = 0's alone)
    v = np.array([3.0, -4.0])
    F = error_matrices(model, "model", v[:, None], u[:, :1], p).F[0]
    np.testing.assert_allclose(F, _drag_derivative(v), rtol=1e-12)
