"""Reading a researcher's hand-coded F and G: a Python function, or sampled matrices.

Two ways in (the layout is documented in ``docs/matrix_check.md``):

* ``FILE.py:FUNCTION``: a Python file defining ``FUNCTION(nav, imu)`` that returns ``F``
  (shape (n, n)) or ``(F, G)`` (G shape (n, m)) as numpy arrays, and module-level lists
  ``STATES`` (n names from the convention's vocabulary, in the order of F's rows) and,
  when G is returned, ``SOURCES`` (m model error-source names, G's columns). ``nav`` and
  ``imu`` are :class:`~ins_errors.checker.navigation.Navigation` and
  :class:`~ins_errors.checker.navigation.Imu`. A function attribute ``FUNCTION.states``
  / ``FUNCTION.sources`` overrides the module lists. ``STATES`` may also name model error
  sources (*bias states*: their column of F is the source's column of G); a dictionary
  ``MARKOV`` (or ``FUNCTION.markov``) gives the correlation time of those that are
  first-order Gauss–Markov biases (s, or a quantity such as ``"1 h"``); the others are
  random constants.
* ``FILE.npz`` or ``FILE.mat``: arrays ``states`` (n strings), optional ``sources`` (m
  strings), ``F_<motion>`` of shape (K, n, n) and optional ``G_<motion>`` of shape
  (K, n, m) for every motion, at the sample times ``t = 0, step, 2 step, …`` of that
  motion (the navigation state at those times is written by ``--write-samples``);
  optional ``markov_states`` (names of bias states) and ``markov_tau`` (their correlation
  times, s).
"""

from __future__ import annotations

import dataclasses
import importlib.util
import sys
import traceback
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ins_errors.checker.navigation import FIELDS, samples
from ins_errors.errors import InsErrorsError, ShapeError


@dataclass
class HandMatrices:
    """A hand-coded linear error model sampled along the checker's motions.

    Attributes
    ----------
    name : str
        What was read (``psi_model.py:psi_model``).
    states : list of str
        The hand model's states (vocabulary names), F's row and column order.
    sources : list of str
        Model error sources of G's columns (empty without G).
    F : dict
        Motion label -> array (K, n, n).
    G : dict
        Motion label -> array (K, n, m); empty without G.
    markov : dict
        Bias state (a model error source among ``states``) -> correlation time of a
        first-order Gauss–Markov bias, s; bias states not in it are random constants.
    """

    name: str
    states: list[str]
    sources: list[str]
    F: dict[str, np.ndarray]
    G: dict[str, np.ndarray]
    markov: dict[str, float] = dataclasses.field(default_factory=dict)


def _names(value, what: str, where: str) -> list[str]:
    if isinstance(value, str) or not hasattr(value, "__iter__"):
        raise InsErrorsError(f"{where}: {what} must be a list of names, got {_short(value)}")
    names = [str(v).strip() for v in np.asarray(value, dtype=object).ravel()]
    if not names:
        raise InsErrorsError(f"{where}: {what} is empty")
    seen = set()
    for n in names:
        if n in seen:
            raise InsErrorsError(f"{where}: {what} lists {n!r} twice")
        seen.add(n)
    return names


def _import_file(path: Path):
    """Import a Python file as a private module; one-line errors for broken files."""
    if not path.is_file():
        raise InsErrorsError(f"hand model file {str(path)!r} does not exist")
    name = f"_ins_errors_hand_{abs(hash(str(path.resolve())))}"
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise InsErrorsError(f"cannot import {str(path)!r} as a Python file")
    module = importlib.util.module_from_spec(spec)
    folder = str(path.resolve().parent)
    sys.path.insert(0, folder)  # the file may import helpers that sit next to it
    try:
        spec.loader.exec_module(module)
    except (Exception, SystemExit) as error:  # the researcher's code: one line (its
        # sys.exit() is its error, not the command's exit status)
        raise InsErrorsError(f"cannot import {path.name}: {_describe(error, path)}") from None
    finally:
        sys.path.remove(folder)
        sys.modules.pop(name, None)
    return module


def _describe(error: BaseException, path: Path | None) -> str:
    """``Type: message (line N)`` with the line in the researcher's file when known."""
    line = ""
    if path is not None:
        frames = [f for f in traceback.extract_tb(error.__traceback__)
                  if Path(f.filename).resolve() == path.resolve()]
        if frames:
            line = f" (line {frames[-1].lineno})"
        elif isinstance(error, SyntaxError) and error.lineno:
            line = f" (line {error.lineno})"
    if isinstance(error, SystemExit):
        return f"called sys.exit({error.code!r}){line}"
    text = " ".join(str(error).split()) or "no message"
    return f"{type(error).__name__}: {text}{line}"


def split_spec(spec: str) -> tuple[Path, str | None]:
    """``FILE.py:FUNCTION`` -> (path, function); ``FILE.npz`` -> (path, None)."""
    path, _, function = spec.rpartition(":")
    if path and path.endswith(".py") and function:
        return Path(path), function
    return Path(spec), None


def load_function(path: Path, function: str):
    """The researcher's function and its ``STATES`` / ``SOURCES`` lists.

    Raises
    ------
    InsErrorsError
        For a missing file or function, an import error, missing or bad state lists.
    """
    return load_hand(path, function)[:3]


def load_hand(path: Path, function: str):
    """The researcher's function, its ``STATES`` / ``SOURCES`` lists and the correlation
    times of its Gauss–Markov bias states (``MARKOV``, s; empty without it).

    Raises
    ------
    InsErrorsError
        For a missing file or function, an import error, missing or bad state lists, a
        ``MARKOV`` that is not a dictionary of positive correlation times.
    """
    module = _import_file(path)
    fn = getattr(module, function, None)
    if not callable(fn):
        found = [n for n, v in vars(module).items() if callable(v) and not n.startswith("_")
                 and getattr(v, "__module__", None) == module.__name__]
        raise InsErrorsError(f"{path.name} has no function {function!r} "
                             f"(functions: {', '.join(found) or 'none'})")
    where = f"{path.name}:{function}"
    return (fn, *_hand_lists(fn, vars(module), where,
                             "define STATES, the list of the model's error states in F's "
                             "row order (names from the convention's vocabulary)"))


def _hand_lists(fn, scope: dict, where: str, missing: str
                ) -> tuple[list[str], list[str], dict[str, float]]:
    """``STATES``, ``SOURCES`` and ``MARKOV`` of a hand function: its attributes
    (``fn.states`` ...), else the names beside it in ``scope`` (its module's or
    notebook's globals); ``missing`` says how to give STATES when neither has it."""
    states = getattr(fn, "states", scope.get("STATES"))
    if states is None:
        raise InsErrorsError(f"{where}: {missing}")
    sources = getattr(fn, "sources", scope.get("SOURCES"))
    markov = getattr(fn, "markov", scope.get("MARKOV"))
    return _names(states, "STATES", where), (
        [] if sources is None else _names(sources, "SOURCES", where)), (
        {} if markov is None else correlation_times(markov, where))


def callable_hand(fn) -> tuple[str, Path | None, list[str], list[str], dict[str, float]]:
    """A function given as an object (defined in a notebook, or imported): its name, its
    file (for the failing line, when it has one), and the ``STATES`` / ``SOURCES`` /
    ``MARKOV`` of :func:`load_hand`, read from the function's attributes or else from the
    globals of the module (or notebook) it was defined in.

    Raises
    ------
    InsErrorsError
        For missing or bad state lists, as :func:`load_hand`.
    """
    where = getattr(fn, "__qualname__", None) or getattr(fn, "__name__", None) or repr(fn)
    code = getattr(fn, "__code__", None)
    path = Path(code.co_filename) if code is not None and Path(code.co_filename).is_file() \
        else None
    return (where, path, *_hand_lists(
        fn, getattr(fn, "__globals__", {}), where,
        f"give the list of the model's error states in F's row order as STATES beside the "
        f"function or as {where}.states = [...] (names from the convention's vocabulary)"))


MIN_CORRELATION_TIME = 1.0
"""Shortest correlation time of a Gauss–Markov bias state, s: the check's propagation
steps a minute (its −1/τ row makes each step's exponential e^(−60 s/τ)); a bias
decorrelating within a second is white noise at that sampling (a column of G), and a τ of
1e-100 s overflowed the propagation into "no effect above rounding"."""


def correlation_times(value, where: str, label: str = "MARKOV",
                      lines: dict[str, int] | None = None) -> dict[str, float]:
    """``MARKOV``: bias state -> correlation time, s (a number of seconds, or a quantity
    with its unit such as ``"1 h"``). ``label`` names the declaration in messages
    (``@markov`` in an equation file), ``lines`` the line of each name's declaration
    there.

    Raises
    ------
    InsErrorsError
        For anything but a dictionary of names to positive finite times; a time of zero
        (white noise, which is no state) is refused with that reason, and so is one
        below :data:`MIN_CORRELATION_TIME`.
    """
    from ins_errors.units import parse_quantity

    if not isinstance(value, dict):
        raise InsErrorsError(f"{where}: {label} must be a dictionary bias state -> "
                             f"correlation time (e.g. {{'accel_bias_x': '1 h'}}), got "
                             f"{_short(value)}")
    white = ("give the source as a column of G (SOURCES) instead" if label == "MARKOV"
             else "write the source in the rows without a line dot(SOURCE) of its own (a "
             "column of G) instead")
    out = {}
    for name, text in value.items():
        line = f", line {lines[name]}" if lines and name in lines else ""
        what = (f"{where}{line}: MARKOV[{name!r}]" if label == "MARKOV"
                else f"{where}{line}: {label} {name}")
        if isinstance(text, bool) or not isinstance(text, (str, int, float, np.number)):
            raise InsErrorsError(f"{what}: expected a correlation time such as 3600 (s) or "
                                 f"'1 h', got {_short(text)}")
        tau = parse_quantity(text if isinstance(text, str) else float(text), "s", what)
        if tau == 0:
            raise InsErrorsError(f"{what}: a correlation time of 0 is white noise, which "
                                 f"cannot be a state: {white}")
        if not 0 < tau < np.inf:
            raise InsErrorsError(f"{what}: the correlation time must be positive and "
                                 f"finite, got {_short(text)}")
        if tau < MIN_CORRELATION_TIME:
            raise InsErrorsError(f"{what}: a correlation time of {tau:g} s is too short for "
                                 f"the check (at least {MIN_CORRELATION_TIME:g} s; its "
                                 f"motions are sampled every minute): noise that fast is "
                                 f"white, {white}")
        out[str(name)] = tau
    return out


def _short(value) -> str:
    """At most 60 characters of ``repr(value)`` on one line (an array's repr has many)."""
    text = " ".join(repr(value).split())
    return text if len(text) <= 60 else text[:57] + "..."


def real_array(value, what: str, where: str) -> np.ndarray:
    """``value`` as a float array; one-line error for anything that is not real numbers.

    A complex array is refused rather than cast (numpy would drop the imaginary part
    with a warning only), and so are strings, even strings of digits.

    Raises
    ------
    ShapeError
        For strings, complex numbers or anything numpy cannot read as real numbers.
    """
    raw = value if isinstance(value, np.ndarray) else None
    if raw is None:
        try:
            raw = np.asarray(value)
        except (TypeError, ValueError):  # ragged nested lists
            raise ShapeError(f"{where}: {what} must be a numeric array, "
                             f"got {_short(value)}") from None
    kind = raw.dtype.kind
    if kind == "c" or (kind == "O" and any(isinstance(v, complex | np.complexfloating)
                                           for v in raw.ravel())):
        raise ShapeError(f"{where}: {what} is complex (dtype {raw.dtype}); "
                         "it must be a real array")
    if kind in "USO" and (kind != "O" or any(isinstance(v, str | bytes)
                                             for v in raw.ravel())):
        raise ShapeError(f"{where}: {what} must be a numeric array, got strings "
                         f"({_short(value)})")
    try:
        return np.asarray(raw, dtype=float)
    except (TypeError, ValueError):
        raise ShapeError(f"{where}: {what} must be a numeric array, "
                         f"got {_short(value)}") from None


def _check_matrix(value, shape: tuple[int, int], what: str, where: str,
                  rows: list[str] | None = None, columns: list[str] | None = None
                  ) -> np.ndarray:
    """``value`` as a real array of ``shape``, finite; one-line errors naming what was
    returned (None: the function returned nothing) and a non-finite entry by its row and
    column names (``rows``, ``columns``; its indices without them)."""
    if value is None:
        raise ShapeError(f"{where}: the function returned None (no return statement "
                         f"reached?); {what} must have shape {shape}")
    array = real_array(value, what, where)
    if array.shape != shape:
        raise ShapeError(f"{where}: {what} must have shape {shape}, got {array.shape}")
    if not np.all(np.isfinite(array)):
        i, j = (int(v[0]) for v in np.nonzero(~np.isfinite(array)))
        bad = "NaN" if np.isnan(array[i, j]) else "infinite"
        named = (f"{what}[{rows[i]}, {columns[j]}] ({what}[{i}, {j}])"
                 if rows is not None and columns is not None else f"{what}[{i}, {j}]")
        raise InsErrorsError(f"{where}: {named} is {bad}")
    return array


def _kept_samples(motion) -> list:
    """The (Navigation, Imu) pairs of a motion, kept on it for the next check.

    Their arrays are read-only: a function that changed its arguments in place would
    otherwise change them for every later check along the motion.
    """
    kept = motion.kept.get("samples")
    if kept is None:
        kept = samples(motion.navigation, motion.times, motion.label)
        for pair in kept:
            for part in pair:
                for value in vars(part).values():
                    if isinstance(value, np.ndarray):
                        value.setflags(write=False)
        motion.kept["samples"] = kept
    return kept


def evaluate_function(fn, name: str, path: Path, states: list[str], sources: list[str],
                      motions, markov: dict[str, float] | None = None) -> HandMatrices:
    """Call the researcher's function at every sample of every motion.

    The function's arguments are read-only (they are kept for the next check).

    Parameters
    ----------
    fn : callable
        ``fn(nav, imu) -> F`` or ``(F, G)``.
    name : str
        ``FILE:FUNCTION``, for messages.
    path : Path
        The file (to point at the failing line).
    states, sources : list of str
        Row names and G's column names.
    motions : list of Motion
        From :func:`ins_errors.checker.check_motions.motions`.
    markov : dict, optional
        Correlation times of Gauss–Markov bias states, s (:func:`correlation_times`).
    """
    n, m = len(states), len(sources)
    F: dict[str, np.ndarray] = {}
    G: dict[str, np.ndarray] = {}
    for motion in motions:
        fs, gs = [], []
        for nav, imu in _kept_samples(motion):
            where = f"{name} on {motion.label} at t = {nav.t:g} s"
            try:
                result = fn(nav, imu)
            except (Exception, SystemExit) as error:  # sys.exit() in it: its error too
                raise InsErrorsError(f"{where}: {_describe(error, path)}") from None
            if isinstance(result, tuple):
                if len(result) != 2:
                    raise ShapeError(f"{where}: return F or (F, G), got a tuple of "
                                     f"{len(result)}")
                f, g = result
                if not m:
                    raise InsErrorsError(f"{where}: G is returned but SOURCES (its columns, "
                                         "model error-source names) is not defined")
                gs.append(_check_matrix(g, (n, m), "G", where, states, sources))
            else:
                f = result
            fs.append(_check_matrix(f, (n, n), "F", where, states, states))
        if gs and len(gs) != len(fs):
            raise ShapeError(f"{name} on {motion.label}: G is returned at some samples only")
        F[motion.label] = np.array(fs)
        if gs:
            G[motion.label] = np.array(gs)
    if m and not G:
        raise InsErrorsError(f"{name}: SOURCES is defined but the function returns F only "
                             "(return (F, G))")
    return HandMatrices(name, states, sources if G else [], F, G, dict(markov or {}))


def _read_arrays(path: Path) -> dict[str, np.ndarray]:
    if not path.is_file():
        raise InsErrorsError(f"matrix file {str(path)!r} does not exist")
    suffix = path.suffix.lower()
    if suffix == ".npz":
        return _read_npz(path)
    if suffix == ".mat":
        return _read_mat(path)
    raise InsErrorsError(f"matrix file {str(path)!r}: expected FILE.py:FUNCTION, FILE.npz or "
                         "FILE.mat")


def _read_npz(path: Path) -> dict[str, np.ndarray]:
    """The arrays of a NumPy ``.npz`` archive (``numpy.savez``); one-line errors."""
    import zipfile

    unreadable = InsErrorsError(f"matrix file {str(path)!r} is not a readable .npz file "
                                "(a zip archive written by numpy.savez)")
    try:
        if not zipfile.is_zipfile(path):  # np.load would take it for a pickle
            raise unreadable
        with np.load(path, allow_pickle=False) as data:
            return {k: data[k] for k in data.files}
    except InsErrorsError:
        raise
    except ValueError as error:
        if "pickle" in str(error):  # an array of Python objects inside the archive
            raise InsErrorsError(f"matrix file {str(path)!r} holds Python objects, not "
                                 "numeric arrays: save plain number and string arrays"
                                 ) from None
        raise unreadable from None
    except OSError as error:
        raise InsErrorsError(f"cannot read matrix file {str(path)!r}: "
                             f"{error.strerror or error}") from None
    except Exception:  # zipfile.BadZipFile, zlib.error, EOFError of a truncated member
        raise unreadable from None


def _read_mat(path: Path) -> dict[str, np.ndarray]:
    """The variables of a MATLAB ``.mat`` file (v4 to v7; v7.3 is HDF5); one-line errors."""
    from scipy.io import loadmat

    try:
        data = loadmat(path, squeeze_me=False, chars_as_strings=True)
    except OSError as error:
        raise InsErrorsError(f"cannot read matrix file {str(path)!r}: "
                             f"{error.strerror or error}") from None
    except NotImplementedError:  # scipy's word for a v7.3 (HDF5) file
        raise InsErrorsError(f"matrix file {str(path)!r} is a MATLAB v7.3 (HDF5) file, "
                             "which is not read: save it with save(..., '-v7')") from None
    except Exception as error:  # scipy: MatReadError, ValueError, IndexError, ... of a
        # truncated, empty or foreign file
        reason = str(error).splitlines()[0] if str(error) else type(error).__name__
        raise InsErrorsError(f"matrix file {str(path)!r} is not a readable .mat file "
                             f"({reason})") from None
    return {k: v for k, v in data.items() if not k.startswith("__")}


def _strings(value: np.ndarray) -> list[str]:
    """Names from an npz string array or a MATLAB char matrix / cell array."""
    array = np.asarray(value)
    if array.dtype == object:  # MATLAB cell array
        return [str(np.asarray(v).ravel()[0]) if np.asarray(v).size else ""
                for v in array.ravel()]
    if array.dtype.kind == "U" and array.ndim >= 1:
        return [str(v).strip() for v in array.ravel()]
    raise InsErrorsError(f"expected an array of names, got dtype {array.dtype}")


def stored_convention(path: Path) -> str | None:
    """The convention a matrix file names in its ``convention`` entry (``ins-errors
    matrices`` writes one), or None where it has none or cannot be read (reading it for
    the check then says why)."""
    try:
        names = _strings(np.asarray(_read_arrays(path)["convention"]).reshape(-1))
    except (InsErrorsError, KeyError):
        return None
    return names[0] if len(names) == 1 and names[0] else None


def read_matrix_file(path: Path, motions) -> HandMatrices:
    """Read sampled F (and G) from ``.npz`` / ``.mat`` (see module docstring).

    Raises
    ------
    InsErrorsError
        For a missing key, wrong shapes or sample counts, non-finite values.
    """
    data = _read_arrays(path)
    where = path.name
    if "states" not in data:
        raise InsErrorsError(f"{where}: no array 'states' (the names of F's rows)")
    states = _names(_strings(data["states"]), "states", where)
    sources = (_names(_strings(data["sources"]), "sources", where)
               if "sources" in data else [])
    n, m = len(states), len(sources)
    markov = {}
    if "markov_states" in data or "markov_tau" in data:
        if "markov_states" not in data or "markov_tau" not in data:
            raise InsErrorsError(f"{where}: give both 'markov_states' (bias states) and "
                                 "'markov_tau' (their correlation times, s)")
        names = _names(_strings(data["markov_states"]), "markov_states", where)
        taus = real_array(data["markov_tau"], "markov_tau", where).ravel()
        if taus.size != len(names):
            raise ShapeError(f"{where}: markov_tau must have {len(names)} values (one per "
                             f"name of markov_states), got {taus.size}")
        markov = correlation_times(dict(zip(names, taus.tolist(), strict=True)), where)
    F, G = {}, {}
    for motion in motions:
        key = f"F_{motion.label}"
        if key not in data:
            raise InsErrorsError(f"{where}: no array {key!r} (F at the {motion.times.size} "
                                 f"sample times of motion {motion.label!r})")
        shape = (motion.times.size, n, n)
        f = real_array(data[key], key, where)
        if f.shape != shape:
            raise ShapeError(f"{where}: {key} must have shape {shape}, got {f.shape}")
        if not np.all(np.isfinite(f)):
            raise InsErrorsError(f"{where}: {key} contains NaN or infinite values")
        F[motion.label] = f
        gkey = f"G_{motion.label}"
        if m:
            if gkey not in data:
                raise InsErrorsError(f"{where}: 'sources' is given but {gkey!r} is missing")
            g = real_array(data[gkey], gkey, where)
            if g.shape != (motion.times.size, n, m):
                raise ShapeError(f"{where}: {gkey} must have shape "
                                 f"{(motion.times.size, n, m)}, got {g.shape}")
            if not np.all(np.isfinite(g)):
                raise InsErrorsError(f"{where}: {gkey} contains NaN or infinite values")
            G[motion.label] = g
    return HandMatrices(where, states, sources, F, G, markov)


def write_samples(path: Path, motions) -> None:
    """Write every motion's sample times and navigation description (.npz or .mat).

    Keys: ``t_<motion>`` (K,), and ``<field>_<motion>`` for every field of
    :data:`~ins_errors.checker.navigation.FIELDS` and the two derived attributes a
    hand function also sees, ``omega_in_n`` (``omega_ie_n + omega_en_n``) and ``f_n``
    (``C_bn @ f_b``), with the sample axis first: (K,), (K, 3) or (K, 3, 3).
    """
    save_arrays(path, sample_arrays(motions), "samples file")


def sample_arrays(motions) -> dict[str, np.ndarray]:
    """The arrays :func:`write_samples` writes, by key: ``t_<motion>`` alone for a motion
    without navigation arrays (a model without a navigation description, written in its
    own error states by ``ins-errors matrices``)."""
    arrays: dict[str, np.ndarray] = {}
    for motion in motions:
        label = motion.label
        arrays[f"t_{label}"] = motion.times
        if not motion.navigation:
            continue
        for field in FIELDS:
            arrays[f"{field}_{label}"] = np.moveaxis(
                np.asarray(motion.navigation[field], dtype=float), -1, 0)
        # the same arithmetic as Navigation.omega_in_n and Imu.f_n, sample by sample
        arrays[f"omega_in_n_{label}"] = (arrays[f"omega_ie_n_{label}"]
                                         + arrays[f"omega_en_n_{label}"])
        arrays[f"f_n_{label}"] = np.array([np.array(c) @ f for c, f in zip(
            arrays[f"C_bn_{label}"], arrays[f"f_b_{label}"], strict=True)]).reshape(-1, 3)
    return arrays


def save_arrays(path: Path, arrays: dict[str, np.ndarray], what: str) -> None:
    """Write ``arrays`` to ``path`` as ``.npz`` or MATLAB ``.mat`` (by its suffix),
    making its missing folders (``--out out/fg.npz`` in a fresh checkout), as the other
    commands' outputs do.

    Raises
    ------
    InsErrorsError
        One line for another suffix (naming ``what`` the file is) or a failed write.
    """
    try:
        if path.suffix.lower() in (".mat", ".npz"):
            path.parent.mkdir(parents=True, exist_ok=True)
        if path.suffix.lower() == ".mat":
            from ins_errors.export import save_mat

            save_mat(path, arrays)  # no date in the header: same samples, same bytes
        elif path.suffix.lower() == ".npz":
            np.savez(path, **arrays)
        else:
            raise InsErrorsError(f"{what} {str(path)!r} must end in .npz or .mat")
    except OSError as error:
        raise InsErrorsError(f"cannot write {str(path)!r}: {error.strerror}") from None
