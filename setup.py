"""Package layout only (metadata lives in pyproject.toml).

The emitted code in ``generated/`` ships inside the package as ``ins_errors.generated``;
its sub-packages (one per model) are discovered here so adding a model needs no edit.
The code writer ``derive/`` ships as ``ins_errors.derive``: ``ins-errors derive FILE`` and
the model-file cache use it from an installed package too.
"""

from setuptools import find_packages, setup

generated = ["ins_errors.generated"] + [
    f"ins_errors.generated.{name}" for name in find_packages("generated")
]
setup(
    packages=find_packages(include=["ins_errors", "ins_errors.*"]) + generated
    + ["ins_errors.derive"],
    package_dir={"ins_errors.generated": "generated", "ins_errors.derive": "derive"},
)
