"""The fingerprint of the code that writes compiled loops' C (part of their cache key):
it changes with anything that writes the C text or runs the compiler, and with nothing
else (comments, docstrings, annotations, code that writes no C)."""

from __future__ import annotations

import importlib.util

import pytest

from ins_errors.numeric import cache as disk
from ins_errors.numeric import writer_key as wk

INTEGRATORS = "ins_errors.numeric.integrators"
TRIG = "ins_errors.numeric.carried_trig"


def _text(module: str) -> str:
    with open(importlib.util.find_spec(module).origin, encoding="utf-8") as handle:
        return handle.read()


def _edited(module: str, old: str, new: str, count: int = 1) -> dict[str, str]:
    text = _text(module)
    assert text.count(old) >= 1, old
    return {module: text.replace(old, new, count)}


@pytest.fixture(scope="module")
def installed() -> str:
    return wk.fingerprint()


def test_comments_docstrings_and_other_code_keep_the_key(installed):
    """Edits that cannot change any C text or build: comments (also inside the writing
    functions), docstrings, annotations, blank lines, and code of functions the writers
    do not use (how a batch is split into threads, the rebuilding of a model's trig)."""
    keeping = [
        (INTEGRATORS, "        check_method(method)\n",
         "        # a new comment inside CompiledLoop.__init__\n        check_method(method)\n"),
        (INTEGRATORS, '    def most(size: str) -> int:\n',
         '    # a comment in the driver writer\n\n    def most(size: str) -> int:\n'),
        (INTEGRATORS, '"""Symbolic one-step map of', '"""Reworded: the symbolic one-step map of'),
        (INTEGRATORS, "def _assume_arguments(source: str) -> str:",
         "def _assume_arguments(source) -> 'str':"),
        (INTEGRATORS, "def worker_count() -> int:\n",
         "def worker_count() -> int:\n    unused = 1 + 1  # noqa\n"),
        (TRIG, "# Taylor coefficients of sin d", "# The Taylor coefficients of sin d"),
        (TRIG, "def with_trig_inputs(", "def with_trig_inputs_renamed("),
    ]
    for module, old, new in keeping:
        assert wk.fingerprint(_edited(module, old, new)) == installed, (module, new)


def test_changes_to_the_c_writing_code_change_the_key(installed):
    """Every change to what writes the C text, the constants it formats, the step's graph
    or the compiler call gives a new key (and each its own)."""
    changing = [
        (INTEGRATORS, "if (r && (r >= whole || r % chunk == 0)) m = INFINITY;",
         "if (r && (r >= whole || r % chunk == 0)) m = HUGE_VAL;"),
        (INTEGRATORS, 'r"if \\(res\\[(\\d+)\\]!=0\\) res\\[\\1\\]", r"res[\\1]"',
         'r"if \\(res\\[(\\d+)\\]!=0\\) res\\[\\1\\]", r"res[\\1] "'),
        (INTEGRATORS, "INLINE_LIMIT = 600", "INLINE_LIMIT = 601"),
        (INTEGRATORS, "return _moved(z, tau / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4), rotations)",
         "return _moved(z, tau * (k1 + 2 * k2 + 2 * k3 + k4) / 6.0, rotations)"),
        (INTEGRATORS, '"-o", str(target), str(c_file), "-lm"]',
         '"-o", str(target), str(c_file), "-lm", "-g"]'),
        (INTEGRATORS, '"-fno-semantic-interposition"', '"-fno-semantic-interposition", "-g"'),
        (TRIG, "_C2, _C4, _C6 = -0.5, 1.0 / 24.0, -1.0 / 720.0",
         "_C2, _C4, _C6 = -0.5, 1.0 / 24.0, -1.0 / 721.0"),
        (TRIG, "*c_out = c - s * d;", "*c_out = c - d * s;"),
        (TRIG, "return 1.0 + d2 * (_C2 + d2 * (_C4 + d2 * _C6))",
         "return 1.0 + d2 * (_C2 + d2 * _C4)"),
    ]
    keys = {installed}
    for module, old, new in changing:
        key = wk.fingerprint(_edited(module, old, new))
        assert key not in keys, (module, new)
        keys.add(key)


def test_the_writing_code_reaches_the_templates_and_the_carried_rotation():
    """What the roots reach: the C templates and flags, the step's graph and the carried
    rotation of carried_trig (C and graph); not the calling or bookkeeping code; every
    name of ROOTS and OTHERS exists (a renamed one would silently leave the key)."""
    code = wk.writer_code()
    for name in ("_DRIVER", "_driver_source", "_assume_arguments", "INLINE_LIMIT",
                 "IEEE_FLAGS", "NO_FOLDING_FLAGS", "casadi_step", "_moved", "generated_source",
                 "compile_source", "CompiledLoop.__init__", "CompiledLoop._build"):
        assert f"{INTEGRATORS}:{name}" in code, name
    for name in ("ROTATE_C", "rotate", "sin_small", "cos_small", "TINY", "_C6", "_S5"):
        assert f"{TRIG}:{name}" in code, name
    for name in ("NativeFunction", "worker_count", "CompiledLoop.run", "_writer_version",
                 "progress_bar"):
        assert f"{INTEGRATORS}:{name}" not in code, name
    assert f"{TRIG}:with_trig_inputs" not in code
    parsed: dict[str, wk._Module] = {}
    for entry in (*wk.OTHERS, *(f"{m}:{n}" for m, names in wk.ROOTS.items() for n in names)):
        module, _, name = entry.partition(":")
        assert importlib.util.find_spec(module) is not None, entry
        if name:
            if module not in parsed:
                parsed[module] = wk._Module(module, _text(module))
            assert name in parsed[module].definitions, entry


def test_the_fingerprint_is_kept_on_disk_and_checked(tmp_path, monkeypatch, installed):
    """Made once per code version and kept in the cache folder; read back without
    reading the syntax trees; a memo naming another module whose text changed is not
    trusted; an unwritable folder only costs the time."""
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    wk.installed_fingerprint.cache_clear()
    try:
        assert wk.installed_fingerprint() == installed
        [memo] = (tmp_path / "notes").glob("writer_*")

        def no_walking(*args):
            raise AssertionError("the syntax trees were read again")

        wk.installed_fingerprint.cache_clear()
        with monkeypatch.context() as patched:
            patched.setattr(wk, "writer_code", no_walking)
            assert wk.installed_fingerprint() == installed
        # a whole note (not one found damaged) naming a module whose text changed
        disk.write_entry(memo, ("f" * 64 + f"\n{TRIG} 0123\n").encode())
        wk.installed_fingerprint.cache_clear()
        assert wk.installed_fingerprint() == installed
        monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path / "file"))
        (tmp_path / "file").write_text("not a folder")
        wk.installed_fingerprint.cache_clear()
        assert wk.installed_fingerprint() == installed
    finally:
        wk.installed_fingerprint.cache_clear()
