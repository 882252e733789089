"""The growth refusal's advice never rounds the longest operating time up: under a
minute it is given in whole seconds below the limit, not as 1 min."""

import pytest

from ins_errors.analysis.budget import _whole_minutes


@pytest.mark.parametrize("seconds, advised", [(0.4, 1.0), (30.7, 30.0), (59.99, 59.0),
                                              (60.0, 60.0), (10271.0, 10260.0)])
def test_the_advised_time_is_at_most_the_limit(seconds, advised):
    assert _whole_minutes(seconds) == advised
    assert advised <= max(seconds, 1.0)
