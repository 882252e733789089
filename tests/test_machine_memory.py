"""Byte counts as people read them (every size a refusal or a store estimate names)."""

from __future__ import annotations

import pytest

from ins_errors.machine_memory import size_text


@pytest.mark.parametrize(("size", "text"), [
    (0, "0 bytes"), (999.4, "999 bytes"), (999.7, "1 kB"), (1500, "1.5 kB"),
    (45e6, "45 MB"), (999.4e6, "999 MB"), (999.6e6, "1 GB"),   # was "1000 MB"
    (5.1e9, "5.1 GB"), (9.94e9, "9.9 GB"), (9.96e9, "10 GB"), (8e12, "8 TB")])
def test_a_size_is_written_in_the_unit_its_rounded_value_belongs_to(size, text):
    assert size_text(size) == text
