"""The LaTeX of a model's generated error equations reads back through `ins-errors check`
as the model's own linearisation: copying the equations out of
generated/<model>/error_equations.md into a hand file gives no finding.

free_azimuth's azimuth angle is spelled δ, as source 002 does; its products were printed
``\\delta \\omega_y``, which the checker (as a reader would) takes for the variation of
ω_y: four false "root mistakes" of size 1. They are printed ``{\\delta} \\omega_y`` now."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from ins_errors.cli import main

ROOT = Path(__file__).resolve().parents[1]
EQUATION = re.compile(r"^\$\$ ((?:\\Delta)?\\dot\{.*) \$\$$")


@pytest.mark.parametrize("model", ["free_azimuth", "orthodromic"])
def test_the_generated_error_equations_check_as_agreeing(model, tmp_path, capsys):
    text = (ROOT / "generated" / model / "error_equations.md").read_text(encoding="utf-8")
    lines = [m.group(1) for line in text.splitlines() if (m := EQUATION.match(line))]
    assert len(lines) >= 5, lines
    hand = tmp_path / f"{model}_generated.tex"
    hand.write_text("\n".join(lines) + "\n", encoding="utf-8")
    status = main(["check", model, str(hand)])
    out = capsys.readouterr().out
    summary = out.strip().splitlines()[-1]
    assert status == 0, summary
    assert f"{len(lines)} agree" in summary and " 0 with mistakes" in summary, summary
