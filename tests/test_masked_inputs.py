"""A numpy masked array given to a Model's functions: its masked entries are refused in
one line, not evaluated as if valid (np.asarray drops the mask and keeps the values
hidden under it); a masked array with nothing masked is a plain array."""

import numpy as np
import pytest

from ins_errors import ShapeError, load_model


@pytest.fixture(scope="module")
def point():
    model = load_model("strapdown_ned")
    p = model.parameter_vector()
    c = model.initial_condition_vector(latitude=np.radians(45.0))
    u = model.input_vector()
    return model, model.initial_state(c, u, p), u, p


def test_a_masked_entry_is_refused_naming_it(point):
    model, x, u, p = point
    hidden = np.ma.masked_array(x.copy(), mask=np.zeros(x.shape, dtype=bool))
    hidden.data[7] = 3.0            # a latitude beyond the pole, hidden under the mask
    hidden[7] = np.ma.masked
    with pytest.raises(ShapeError, match=r"x has masked entries \(first at index 7\)"):
        model.state_matrix(hidden, u, p)


def test_a_masked_array_without_masked_entries_is_its_values(point):
    model, x, u, p = point
    plain = model.state_matrix(x, u, p)
    masked = model.state_matrix(np.ma.masked_array(x, mask=False), u, p)
    assert np.array_equal(np.asarray(masked), plain)
