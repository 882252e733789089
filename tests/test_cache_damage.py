"""Damaged cache entries are found before use and made again (docs/cache.md).

Every entry whose contents feed numbers is sealed when it is written (its hash and
length appended, written whole through a scratch file and a rename) and checked when it
is read: a note cut short once compiled a wrong latitude into the loop (exit 0, δlat
2.8e3 arcmin instead of 0.68), a compiled loop cut short killed the process (SIGBUS), a
cut generated module or stored motion set gave a traceback. The numbers a run gives
after the repair are checked against the CasADi virtual machine, which reads no note
and loads no library.

Also here: what the README says of the no-compiler fallback, the same bits as the
compiled loops, checked on a moving motion (it was not: the functions of the true
motion were compiled with fused multiply-add).
"""

from __future__ import annotations

import io
import os
import re
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from ins_errors.numeric import cache
from ins_errors.numeric import integrators as integ
from tests.test_cache_read_only import read_only  # noqa: F401 (a fixture)

ROOT = Path(__file__).resolve().parent.parent
SCHULER = ROOT / "examples" / "own_model" / "schuler_loop.py"
STATIC = ["compare", "schuler_loop.py", "--source", "accel_bias=100ug", "--hours", "1",
          "--json", "--no-progress"]


def _run(arguments: list[str], folder: Path, cache_folder: Path,
         **environment: str | None) -> subprocess.CompletedProcess:
    """``ins-errors ARGUMENTS`` in ``folder`` with the cache ``cache_folder`` (a new
    process: nothing of this one's memory is reused); ``environment`` sets (a value) or
    removes (None) variables."""
    env = {**os.environ, "INS_ERRORS_CACHE": str(cache_folder)}
    env.pop("INS_ERRORS_NO_JIT", None)
    for name, value in environment.items():
        if value is None:
            env.pop(name, None)
        else:
            env[name] = value
    return subprocess.run([sys.executable, "-m", "ins_errors", *arguments], cwd=folder,
                          env=env, capture_output=True, text=True, timeout=600)


def _damage_lines(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if "damaged" in line]


@pytest.fixture(scope="module")
def warm(tmp_path_factory) -> tuple[Path, Path, str]:
    """A folder with the Schuler-loop model file, a cache folder the static comparison
    has filled (its loops, notes and generated package), and that comparison's output."""
    if integ._compiler() is None:
        pytest.skip("no C compiler")
    base = tmp_path_factory.mktemp("warm")
    shutil.copy(SCHULER, base / SCHULER.name)
    done = _run(STATIC, base, base / "cache")
    assert done.returncode == 0, done.stderr
    return base, base / "cache", done.stdout


@pytest.fixture
def copy(warm, tmp_path) -> tuple[Path, Path, str]:
    """A copy of :func:`warm` of this test's own (its damage stays its own)."""
    base, cache_folder, out = warm
    shutil.copy(base / SCHULER.name, tmp_path / SCHULER.name)
    shutil.copytree(cache_folder, tmp_path / "cache", symlinks=True)
    return tmp_path, tmp_path / "cache", out


@pytest.fixture
def quiet(monkeypatch):
    """This process's 'damaged' notices not yet given."""
    monkeypatch.setattr(cache, "_DAMAGE_SAID", set())


# --------------------------------------------------------------------------------------
# the seal
# --------------------------------------------------------------------------------------
def test_the_seal_refuses_every_cut_and_every_change():
    data = bytes(range(256)) * 3 + b"frozen\n1 0x1.becde5da115a9p-1\n"
    sealed = cache.sealed(data)
    assert cache.unsealed(sealed) == data
    assert cache.unsealed(cache.sealed(b"")) == b""
    for size in range(len(sealed)):
        assert cache.unsealed(sealed[:size]) is None, size
    for position in range(0, len(sealed), 7):
        changed = bytearray(sealed)
        changed[position] ^= 0x01
        assert cache.unsealed(bytes(changed)) is None, position
    assert cache.unsealed(sealed + b"\n") is None
    assert cache.unsealed(data) is None   # never sealed


# --------------------------------------------------------------------------------------
# notes: the wrong number
# --------------------------------------------------------------------------------------
def test_a_cut_frozen_note_is_worked_out_again_never_compiled_in(copy):
    """Was: exit 0 with the latitude cut in the note compiled into the loop, on every
    later run (the note was never written again)."""
    folder, cache_folder, reference = copy
    notes = sorted(cache_folder.glob("notes/frozen_*"))
    assert notes
    for note in notes:
        data = note.read_bytes()
        # the start latitude, 50°, as a hexadecimal float: cut in its mantissa, the text
        # left still reads as a number (0x1.bec: 49.9...°)
        number = re.search(rb"0x1\.[0-9a-f]{13}p-1", data)
        assert number is not None, data
        note.write_bytes(data[:number.start() + 7])
    done = _run(STATIC, folder, cache_folder)
    assert done.returncode == 0, done.stderr
    assert done.stdout == reference
    said = _damage_lines(done.stderr)
    assert len(said) == 1 and "notes" in said[0] and "working its answer out again" in said[0]
    for note in cache_folder.glob("notes/frozen_*"):   # written again, whole
        assert cache.unsealed(note.read_bytes()) is not None, note
    again = _run(STATIC, folder, cache_folder)
    assert again.stdout == reference and not _damage_lines(again.stderr)
    # the virtual machine reads no note and loads no library: the same bits
    virtual = _run(STATIC, folder, cache_folder, INS_ERRORS_NO_JIT="1")
    assert virtual.returncode == 0 and virtual.stdout == reference


# --------------------------------------------------------------------------------------
# compiled loops
# --------------------------------------------------------------------------------------
LOOP_SCRIPT = """
import numpy as np, casadi as ca
from ins_errors.numeric import integrators as integ
x = ca.SX.sym("x")
f = ca.Function("damage_probe", [x], [ca.sin(x) * x + 1.5])
call = integ.native_functions([f])[0]
assert type(call).__name__ == "NativeFunction", type(call)
values = []
for v in (0.1, 1.0, 2.5):
    out = np.empty(1)
    call([np.array([v])], [out])
    values.append(out[0].hex())
print(" ".join(values))
print(integ.compile_library([f]))
"""


def _probe(cache_folder: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "INS_ERRORS_CACHE": str(cache_folder)}
    env.pop("INS_ERRORS_NO_JIT", None)
    return subprocess.run([sys.executable, "-c", LOOP_SCRIPT], env=env,
                          capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize("damage", ["cut to 1000 bytes", "emptied", "garbage",
                                    "last byte cut", "one byte changed"])
def test_a_damaged_compiled_library_is_compiled_again_never_loaded(tmp_path, damage):
    """Was: a library cut short killed the process (SIGBUS, nothing said), an empty or
    garbage one failed with 'cannot use: ... file too short' on every run."""
    if integ._compiler() is None:
        pytest.skip("no C compiler")
    first = _probe(tmp_path)
    assert first.returncode == 0, first.stderr
    values, library = first.stdout.split("\n")[:2]
    library = Path(library)
    expected = values.split()
    inputs = np.array([0.1, 1.0, 2.5])
    assert np.allclose([float.fromhex(v) for v in expected], np.sin(inputs) * inputs + 1.5,
                       rtol=1e-15, atol=0)
    data = library.read_bytes()
    damaged = {"cut to 1000 bytes": data[:1000], "emptied": b"",
               "garbage": bytes(range(256)) * 16, "last byte cut": data[:-1],
               "one byte changed": data[:len(data) // 2] + bytes([data[len(data) // 2] ^ 1])
               + data[len(data) // 2 + 1:]}[damage]
    library.write_bytes(damaged)
    again = _probe(tmp_path)
    assert again.returncode == 0, (again.returncode, again.stderr[-2000:])
    assert again.stdout.split("\n")[0].split() == expected
    said = _damage_lines(again.stderr)
    assert len(said) == 1 and str(library) in said[0] and "compiling it again" in said[0]
    assert cache.intact(library)   # compiled again in its place
    assert sorted(tmp_path.glob(cache.PATTERN)) == [library]
    assert not _damage_lines(_probe(tmp_path).stderr)


def test_a_stored_library_is_sealed_and_checked(tmp_path, monkeypatch, quiet):
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    x = ca.SX.sym("x")
    functions = [ca.Function("sealed_probe", [x], [x * 3])]
    library = integ.compile_library(functions)
    if library is None:
        pytest.skip("no C compiler")
    assert cache.intact(library)
    library.write_bytes(library.read_bytes()[:-100])
    with pytest.warns(RuntimeWarning, match="is damaged .* compiling it again"):
        again = integ.compile_library(functions)
    assert again == library and cache.intact(library)
    assert float(ca.external("sealed_probe", str(library))(2.0)) == 6.0


# --------------------------------------------------------------------------------------
# generated code of model files
# --------------------------------------------------------------------------------------
def test_a_cut_generated_module_in_the_cache_is_derived_again(copy):
    """Was: a 29-line traceback, exit 1 (for `check`, the status of a mistake found)."""
    folder, cache_folder, reference = copy
    (module,) = cache_folder.glob("models/*/numpy_model.py")
    module.write_bytes(module.read_bytes()[:5000])
    done = _run(STATIC, folder, cache_folder)
    assert done.returncode == 0, done.stderr
    assert done.stdout == reference
    said = _damage_lines(done.stderr)
    assert len(said) == 1 and "numpy_model.py is cut short or altered" in said[0]
    assert str(module.parent) in said[0]
    assert done.stderr.count("\n") == 1   # the one line, not also "deriving ... first use"
    again = _run(STATIC, folder, cache_folder)
    assert again.stdout == reference and again.stderr == ""


def test_a_cut_package_beside_the_model_file_is_derived_again_in_its_place(copy):
    folder, cache_folder, reference = copy
    derived = _run(["derive", SCHULER.name], folder, cache_folder)
    assert derived.returncode == 0, derived.stderr
    beside = folder / "schuler_loop_generated"
    for name in ("numpy_model.py", "__init__.py"):
        path = beside / name
        path.write_bytes(path.read_bytes()[:-40])
        done = _run(STATIC, folder, cache_folder)
        assert done.returncode == 0, done.stderr
        assert done.stdout == reference
        said = _damage_lines(done.stderr)
        assert len(said) == 1 and "schuler_loop_generated/ is damaged" in said[0], said
        assert f"{name} is cut short or altered" in said[0]
        again = _run(STATIC, folder, cache_folder)
        assert again.stdout == reference and again.stderr == ""   # written again, whole


def test_a_damaged_package_beside_the_model_file_that_cannot_be_written_is_refused(
        copy, read_only):  # noqa: F811
    folder, cache_folder, _ = copy
    assert _run(["derive", SCHULER.name], folder, cache_folder).returncode == 0
    beside = folder / "schuler_loop_generated"
    module = beside / "numpy_model.py"
    module.write_bytes(module.read_bytes()[:5000])
    read_only(beside)
    done = _run(STATIC, folder, cache_folder)
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr.count("\n") == 1, done.stderr
    assert done.stderr.startswith(f"ins-errors: error: the generated package "
                                  f"{str(beside)!r} is damaged (numpy_model.py is cut "
                                  "short or altered)")
    assert "delete the folder" in done.stderr


# --------------------------------------------------------------------------------------
# the other stores
# --------------------------------------------------------------------------------------
def _cut(path: Path) -> None:
    path.write_bytes(path.read_bytes()[:len(path.read_bytes()) // 2])


def test_damaged_stored_motions_propagations_variations_and_functions_are_made_again(
        tmp_path, monkeypatch, quiet):
    """Was: a stored motion set cut short stopped ``check`` with BadZipFile (exit 1)."""
    from ins_errors.checker import motion_store, propagation_store
    from ins_errors.studies import function_cache
    from ins_errors.symbolic import variation_store

    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    rng = np.random.default_rng(5)
    fields = {f: rng.standard_normal((3, 40)) for f in motion_store.FIELDS}
    motion_store.store("probe", [("cruise", "a cruise", fields)], ["turn: too steep"])
    phis = tuple(rng.standard_normal((4, 4)) for _ in range(3))
    propagation_store.store("probe", phis)
    variation_store.store("probe", [("line", 1.5)])
    x = ca.SX.sym("x")
    function_cache.write("probe", {"f": ca.Function("f", [x], [x * x])})
    paths = {"motions": motion_store.folder() / "probe.npz",
             "transitions": propagation_store.folder() / "probe.npy",
             "variations": variation_store.folder() / "probe.pickle",
             "functions": function_cache._file("probe")}

    def loads() -> dict:
        return {"motions": motion_store.load("probe"),
                "transitions": propagation_store.load("probe"),
                "variations": variation_store.load("probe"),
                "functions": function_cache.read("probe", ["f"])}

    whole = loads()
    assert all(value is not None for value in whole.values())
    (label, text, arrays), = whole["motions"][0]
    assert (label, text, whole["motions"][1]) == ("cruise", "a cruise", ["turn: too steep"])
    assert all(np.array_equal(arrays[f], fields[f]) for f in fields)
    assert all(np.array_equal(a, b) for a, b in zip(whole["transitions"], phis, strict=True))
    assert whole["variations"] == [("line", 1.5)]
    assert float(whole["functions"][0](3.0)) == 9.0
    for path in paths.values():
        _cut(path)
    with pytest.warns(RuntimeWarning) as notices:
        damaged = loads()
    assert damaged == dict.fromkeys(paths)   # none used: each is made again
    said = sorted(str(n.message) for n in notices)
    assert len(said) == 4
    for path in paths.values():
        assert sum(f"{str(path)!r} is damaged" in text for text in said) == 1, path


def test_a_damaged_set_of_parsed_units_is_parsed_again(tmp_path, monkeypatch, quiet):
    """pint cannot read a file of its parsed set cut short: the set is deleted and parsed
    again (before, every process parsed afresh, 0.3 s, and the set stayed damaged)."""
    from ins_errors import units

    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    assert units._cached_registry() is not None
    parsed = sorted(tmp_path.glob("units/*/*.pickle"))
    assert parsed
    sizes = {path.name: path.stat().st_size for path in parsed}
    for path in parsed:
        _cut(path)
    with pytest.warns(RuntimeWarning, match="is damaged .* parsing pint's unit definitions"):
        registry = units._cached_registry()
    assert registry is not None
    assert registry.Quantity(1, "nautical_mile").to("m").magnitude == 1852.0
    assert {p.name: p.stat().st_size for p in tmp_path.glob("units/*/*.pickle")} == sizes


# --------------------------------------------------------------------------------------
# processes sharing a cache
# --------------------------------------------------------------------------------------
def test_two_commands_started_together_on_a_fresh_cache_both_succeed_alike(tmp_path):
    if integ._compiler() is None:
        pytest.skip("no C compiler")
    shutil.copy(SCHULER, tmp_path / SCHULER.name)
    env = {**os.environ, "INS_ERRORS_CACHE": str(tmp_path / "cache")}
    env.pop("INS_ERRORS_NO_JIT", None)
    runs = [subprocess.Popen([sys.executable, "-m", "ins_errors", *STATIC], cwd=tmp_path,
                             env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True) for _ in range(2)]
    done = [(*run.communicate(timeout=600), run.returncode) for run in runs]
    assert [status for _, _, status in done] == [0, 0], [err for _, err, _ in done]
    assert done[0][0] == done[1][0]
    assert not any(_damage_lines(err) for _, err, _ in done)
    for path in (tmp_path / "cache").rglob("*"):   # no scratch file left behind
        assert not path.name.startswith(".") or path.name == ".compiling", path


# --------------------------------------------------------------------------------------
# the virtual machine's bits
# --------------------------------------------------------------------------------------
def test_compiled_functions_round_every_operation_as_the_virtual_machine(tmp_path,
                                                                        monkeypatch):
    """x y + z with x = y = 1 + 2⁻³⁰, z = −(1 + 2⁻²⁹): the product rounds to 1 + 2⁻²⁹ and
    the sum is 0, as the virtual machine gives; one fused multiply-add (what the C
    compiler made of CasADi's two statements where the processor has it) gives 2⁻⁶⁰."""
    monkeypatch.setenv("INS_ERRORS_CACHE", str(tmp_path))
    x, y, z = ca.SX.sym("x"), ca.SX.sym("y"), ca.SX.sym("z")
    function = ca.Function("fused_probe", [x, y, z], [x * y + z])
    (native,) = integ.native_functions([function])
    if isinstance(native, integ.VirtualFunction):
        pytest.skip("no C compiler")
    a, c = 1.0 + 2.0**-30, -(1.0 + 2.0**-29)
    args = [np.array([a]), np.array([a]), np.array([c])]
    out, virtual = np.empty(1), np.empty(1)
    native(args, [out])
    integ.VirtualFunction(function)(args, [virtual])
    assert virtual[0] == 0.0
    assert out[0] == 0.0


def test_without_a_compiler_a_moving_motion_gives_the_compiled_bits():
    """The README: without a compiler the loops run in CasADi's virtual machine, 'from
    the same inputs both give the same bits'. Was: along a moving motion the true
    motion's inputs were compiled with fused multiply-add (the direct δv_N 4.4e-16 off)."""
    if integ._compiler() is None:
        pytest.skip("no C compiler")
    arguments = ["compare", "orthodromic", "--motion", "manoeuvre", "--hours", "0.02",
                 "--step", "0.05s", "--source", "accel_bias_x=100ug", "--json",
                 "--no-progress"]
    env = {**os.environ}
    env.pop("INS_ERRORS_NO_JIT", None)
    compiled = subprocess.run([sys.executable, "-m", "ins_errors", *arguments], env=env,
                              capture_output=True, text=True, timeout=600)
    env.pop("CC", None)
    env["PATH"] = str(Path(sys.executable).parent)   # no cc, gcc, clang
    virtual = subprocess.run([sys.executable, "-m", "ins_errors", *arguments], env=env,
                             capture_output=True, text=True, timeout=600)
    assert compiled.returncode == virtual.returncode == 0, virtual.stderr
    assert "no working C compiler" in virtual.stderr
    assert "no working C compiler" not in compiled.stderr
    assert compiled.stdout == virtual.stdout


def test_write_entry_leaves_no_scratch_file_and_is_whole_for_a_reader(tmp_path):
    path = tmp_path / "store" / "entry.npz"
    data = io.BytesIO()
    np.savez(data, a=np.arange(5.0))
    cache.write_entry(path, data.getvalue())
    assert [p.name for p in path.parent.iterdir()] == ["entry.npz"]
    assert cache.read_entry(path, "again") == data.getvalue()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert cache.read_entry(tmp_path / "none.npz", "again") is None   # missing: silent


def test_cache_entries_and_generated_folders_are_readable_by_others(tmp_path):
    """A cache shared by a group (INS_ERRORS_CACHE on a common file system) and a shared
    checkout: entries written whole through a scratch file took mkstemp's private mode
    0600, and `make derive` left generated/ as mkdtemp's 0700."""
    old = os.umask(0o022)
    try:
        for mask, mode in ((0o002, 0o664), (0o022, 0o644)):  # a group's umask and the usual
            os.umask(mask)
            entry = tmp_path / "cache" / "notes" / f"{mask:o}.entry"
            cache.replace_file(entry, b"data")
            assert entry.stat().st_mode & 0o777 == mode
        from derive.pipeline import derive_all

        derive_all(tmp_path / "generated", ["free_azimuth"])
        assert (tmp_path / "generated").stat().st_mode & 0o777 == 0o755
    finally:
        os.umask(old)
