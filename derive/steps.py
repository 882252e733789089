"""One-line errors of derivation steps (``make derive`` / ``ins-errors derive``)."""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from ins_errors.errors import InsErrorsError


class DeriveError(InsErrorsError):
    """A derivation step failed; nothing was replaced."""


@contextlib.contextmanager
def step(model: str, what: str) -> Iterator[None]:
    """Turn any failure inside the block into a one-line :class:`DeriveError`."""
    try:
        yield
    except InsErrorsError:  # already one line naming the problem (e.g. the model's quantity)
        raise
    except Exception as error:  # any failure of SymPy or of a model definition
        text = str(error).strip().splitlines()
        detail = f"{type(error).__name__}: {text[0][:200]}" if text else type(error).__name__
        raise DeriveError(f"model {model}, step '{what}' failed: {detail}") from None
