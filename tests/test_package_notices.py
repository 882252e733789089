"""The notices about a model file's stale or damaged generated package are warnings.

A package beside the model file (``my_ins_generated/``) or in the cache that is stale
(the file was edited, another version of ins-errors derived it) or damaged is never run:
the code is derived again and a notice says so (deriving a version not yet in the cache,
for its first use or after an upgrade of ins-errors, is said as progress on stderr).
The notice is a RuntimeWarning: the Python API catches or filters it (it was printed on
stderr, beyond any filter), the command line prints its one line, and
``--fail-on-warning`` does not count it (the results are those of the model as it is).
The built-in models' notice: tests/test_stale_builtin.py.
"""

from __future__ import annotations

import hashlib
import math
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest

from ins_errors import InsErrorsNotice, load_model, model_lookup
from ins_errors.cli import main
from ins_errors.numeric.model import _file_model
from tests.helpers import fresh_model_cache

ROOT = Path(__file__).resolve().parent.parent
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"
R = 6_371_000.0
OTHER_CODE = hashlib.sha256(b"another version of ins-errors").hexdigest()


@pytest.fixture(autouse=True)
def private_cache(tmp_path, monkeypatch):
    """A fresh model cache, no model loaded and no notice given yet (a new process)."""
    monkeypatch.setattr(model_lookup, "_NOTICES_GIVEN", set(), raising=False)
    monkeypatch.delenv("INS_ERRORS_PACKAGE_NOTICES_GIVEN", raising=False)
    yield fresh_model_cache(tmp_path, monkeypatch)
    _file_model.cache_clear()


def _model_file(tmp_path: Path) -> Path:
    path = tmp_path / "my_ins.py"
    shutil.copy(SCHULER, path)
    return path


def _load(path: Path):
    _file_model.cache_clear()   # as a new command would
    return load_model(str(path))


def _gravity(model) -> float:
    """g (m/s²) from the Schuler frequency √(g/R) of the loop's state matrix."""
    F = model.state_matrix(np.zeros(2), np.zeros(1))
    return float(np.max(np.linalg.eigvals(F).imag)) ** 2 * R


def _cut(path: Path) -> None:
    path.write_bytes(path.read_bytes()[:len(path.read_bytes()) // 2])


def test_a_filtered_stale_notice_says_nothing(tmp_path, capsys):
    """Was: the line on stderr whatever the warnings filter."""
    path = _model_file(tmp_path)
    assert main(["derive", str(path)]) == 0
    path.write_text(path.read_text(encoding="utf-8").replace("9.80665", "9.5"),
                    encoding="utf-8")
    capsys.readouterr()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = _load(path)
    assert capsys.readouterr().err == ""
    assert model.folder != tmp_path / "my_ins_generated"
    assert math.isclose(_gravity(model), 9.5, rel_tol=1e-9)   # the edited file ran


def test_the_model_file_notices_are_warnings_fail_on_warning_does_not_count(
        tmp_path, monkeypatch, capsys):
    """Each notice about a stale or damaged package of a model file, in its own words,
    as the product gives it: a RuntimeWarning, none counted by ``--fail-on-warning``."""
    from ins_errors.commands.warning_status import watched_warnings

    path = _model_file(tmp_path)
    beside = tmp_path / "my_ins_generated"
    assert main(["derive", str(path)]) == 0
    capsys.readouterr()
    said: list[tuple[type, str]] = []
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        warnings.showwarning = lambda message, category, *args, **kwargs: said.append(
            (category, str(message)))
        with watched_warnings() as counted:
            _cut(beside / "numpy_model.py")
            assert _load(path).folder == beside                  # derived again there
            with monkeypatch.context() as other:
                other.setattr("ins_errors.model_identity.derivation_code_sha256",
                              lambda: OTHER_CODE)
                assert _load(path).folder != beside
            path.write_text(path.read_text(encoding="utf-8") + "\n# edited\n",
                            encoding="utf-8")
            cached = _load(path).folder
            _cut(cached / "numpy_model.py")
            assert _load(path).folder == cached                  # made again
    assert capsys.readouterr().err == ""
    assert [category for category, _ in said] == [InsErrorsNotice] * 4
    texts = [text for _, text in said]
    assert texts[0] == ("ins-errors: my_ins_generated/ is damaged (numpy_model.py is cut "
                        "short or altered); deriving it again")
    assert texts[1] == ("ins-errors: my_ins_generated/ was derived by another version of "
                        "ins-errors; deriving again into the cache")
    assert texts[2] == ("ins-errors: my_ins_generated/ is stale (my_ins.py or a file it "
                        "imports changed since it was derived); deriving again into the "
                        "cache")
    assert texts[3] == (f"ins-errors: the cached code {str(cached)!r} is damaged "
                        "(numpy_model.py is cut short or altered) and is not used; "
                        "deriving model file my_ins.py again")
    assert counted == []
