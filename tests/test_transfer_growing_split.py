"""GrowingSplit.of returns None, as its docstring says, where the Schur reordering
cannot separate the growing eigenvalues (scipy raises for a real part at the
threshold itself): no traceback reaches the transfer command."""

from unittest import mock

import numpy as np
import scipy.linalg

from ins_errors.analysis.transfer_reduction import GrowingSplit


def test_a_reordering_that_cannot_separate_gives_no_split():
    A = np.diag([0.5, -0.5, 0.1])
    split = GrowingSplit.of(A, 0.0)
    assert split is not None and split.k == 2  # the two growing modes, separated
    refusal = scipy.linalg.LinAlgError("Eigenvalues could not be separated for reordering")
    with mock.patch("scipy.linalg.schur", side_effect=refusal):
        assert GrowingSplit.of(A, 0.0) is None
