"""What a Dask worker or the Dask scheduler imports to run sweep, Monte Carlo and validity
tasks stays light: none of SciPy, pint, SymPy, matplotlib, xarray, zarr or pandas at
module level (each costs 0.2-0.8 s CPU in every worker process that imports it).

The scheduler unpickles each task, importing the module of its function; a worker also
runs it, importing what the function imports when it is called. The modules below are
followed through their module-level imports (``if TYPE_CHECKING:`` blocks excepted);
imports inside functions run only where they are needed.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
HEAVY = {"scipy", "pint", "sympy", "matplotlib", "xarray", "zarr", "pandas"}
TASK_MODULES = [
    "ins_errors.analysis.sweep",        # run_point
    "ins_errors.analysis.monte_carlo",  # _direct_block
    "ins_errors.analysis.validity",     # run_validity_task
    # what those functions import when they run
    "ins_errors.numeric.compare", "ins_errors.numeric.simulate",
    "ins_errors.numeric.trajectories", "ins_errors.numeric.motion_spec",
    "ins_errors.numeric.model", "ins_errors.numeric.integrators",
]


def _file(module: str) -> Path | None:
    parts = module.split(".")
    if parts[0] != "ins_errors":
        return None
    base = ROOT.joinpath(*parts)
    for path in (base.with_suffix(".py"), base / "__init__.py"):
        if path.is_file():
            return path
    return None


def _module_level_imports(path: Path) -> set[str]:
    """Modules imported by the statements run when ``path`` is imported."""
    found: set[str] = set()

    def visit(body) -> None:
        for node in body:
            if isinstance(node, ast.Import):
                found.update(alias.name for alias in node.names)
            elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
                found.add(node.module)
                found.update(f"{node.module}.{alias.name}" for alias in node.names)
            elif isinstance(node, ast.If):
                if not (isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING"):
                    visit(node.body)
                visit(node.orelse)
            elif isinstance(node, ast.Try):
                visit(node.body)
                for handler in node.handlers:
                    visit(handler.body)
                visit(node.orelse)
                visit(node.finalbody)

    visit(ast.parse(path.read_text(encoding="utf-8")).body)
    return found


def imported_by(modules: list[str]) -> set[str]:
    """Every module (top-level name outside the package) reached at module level."""
    seen, outside, todo = set(), set(), list(modules)
    while todo:
        module = todo.pop()
        parts = module.split(".")
        for k in range(1, len(parts) + 1):  # a module's packages are imported first
            name = ".".join(parts[:k])
            if name in seen:
                continue
            seen.add(name)
            path = _file(name)
            if path is None:
                if parts[0] != "ins_errors":
                    outside.add(parts[0])
                continue
            todo.extend(_module_level_imports(path))
    return outside


def test_task_modules_import_nothing_heavy():
    outside = imported_by(TASK_MODULES)
    assert "numpy" in outside and "casadi" in outside  # the walk follows the imports
    assert not outside & HEAVY, sorted(outside & HEAVY)


def test_the_walk_sees_a_heavy_import(tmp_path):
    """The check fails for a module-level import of SciPy (what covariance.py had)."""
    path = tmp_path / "m.py"
    path.write_text("from typing import TYPE_CHECKING\nimport numpy as np\n"
                    "from scipy.linalg import expm\nif TYPE_CHECKING:\n    import pint\n"
                    "def f():\n    import sympy\n", encoding="utf-8")
    assert _module_level_imports(path) == {"typing", "typing.TYPE_CHECKING", "numpy",
                                           "scipy.linalg", "scipy.linalg.expm"}
