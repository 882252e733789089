"""User text (case labels, titles, file names) in the Markdown and HTML reports: a ``|``
stays in its table cell, and HTML in it is shown as text, never read as markup."""

from __future__ import annotations

import json
import re
from html.parser import HTMLParser

import pytest

from ins_errors.cli import main

PIPE = "gyro x | 0.01 deg/h"
MARKUP = "a<b & c>d <script>alert(1)</script> \\| end"
MOTION = "fl | ight.csv"

SCENARIO = f"""title = "labels <i>with</i> | pipes"
model = "orthodromic"
[motion]
kind = "file"
file = {json.dumps(MOTION)}
latitude = "50 deg"
[run]
duration = "6 min"
step = "10 s"
[[case]]
label = {json.dumps(PIPE)}
gyro_drift_x = "0.01 deg/h"
[[case]]
label = {json.dumps(MARKUP)}
gyro_drift_y = "0.01 deg/h"
"""


def _cells(row: str) -> list[str]:
    """The cells of a Markdown table row as GitHub's table extension splits them: at
    each ``|`` not escaped by a backslash (a backslash escapes the next character), the
    escapes ``\\|`` and ``\\\\`` then read as ``|`` and ``\\``."""
    cells, cell, k = [], "", 0
    body = row.strip()[1:-1] if row.strip().endswith("|") else row.strip()[1:]
    while k < len(body):
        if body[k] == "\\" and k + 1 < len(body):
            cell += body[k:k + 2]
            k += 2
            continue
        if body[k] == "|":
            cells.append(cell)
            cell = ""
        else:
            cell += body[k]
        k += 1
    cells.append(cell)
    return [re.sub(r"\\([|\\])", r"\1", c).strip() for c in cells]


class _Page(HTMLParser):
    """Every element the page opens, and the text of each table row's cells."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.tags: list[str] = []
        self.links: list[str] = []
        self.rows: list[list[str]] = []
        self._cell: str | None = None

    def handle_starttag(self, tag, attrs):
        self.tags.append(tag)
        if tag == "tr":
            self.rows.append([])
        elif tag in ("td", "th"):
            self._cell = ""
        elif tag == "a":
            self.links.append(dict(attrs).get("href", ""))

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self.rows[-1].append(self._cell.strip())
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    folder = tmp_path_factory.mktemp("labels")
    (folder / "s.toml").write_text(SCENARIO, encoding="utf-8")
    (folder / MOTION).write_text("t,v_N,v_E\n" + "".join(f"{t},100,20\n"
                                                         for t in range(0, 361, 10)))
    assert main(["run", str(folder / "s.toml"), "--out", str(folder / "out"),
                 "--no-progress"]) == 0
    out = folder / "out"
    return (json.loads((out / "results.json").read_text(encoding="utf-8")),
            (out / "report.md").read_text(encoding="utf-8"),
            (out / "report.html").read_text(encoding="utf-8"))


def _summary_rows(lines: list[str]) -> list[list[str]]:
    start = next(k for k, line in enumerate(lines) if line.startswith("| case |"))
    rows = []
    for line in lines[start + 2:]:
        if not line.startswith("|"):
            break
        rows.append(_cells(line))
    return rows


def test_a_label_with_a_pipe_stays_in_its_cell_of_report_md(report):
    """Each summary row has the header's six cells, the first the label as written and
    the second the case's worst linear ratio of results.json."""
    results, text, _ = report
    lines = text.splitlines()
    motion = _cells(next(line for line in lines if line.startswith("| motion |")))
    assert len(motion) == 2 and MOTION in motion[1]  # the file's name, whole
    rows = _summary_rows(lines)
    assert [row[0] for row in rows] == [PIPE, MARKUP]
    for row, case in zip(rows, results["cases"], strict=True):
        assert len(row) == 6
        assert float(row[1]) == pytest.approx(case["worst_linear_ratio"], rel=1e-3)
    # the case tables' rows: as many cells as their header
    cases = lines[:lines.index("## Equations used")]
    assert sum(line.startswith("| `") for line in cases) == sum(
        len(case["metrics"]) for case in results["cases"])
    for line in cases:
        if line.startswith("| `"):
            assert len(_cells(line)) == 11, line


def test_the_html_tables_keep_the_label_in_one_cell_and_show_markup_as_text(report):
    results, _, page = report
    parsed = _Page()
    parsed.feed(page)
    assert "script" not in parsed.tags and "i" not in parsed.tags and "b" not in parsed.tags
    assert "<script>" not in page and "&lt;script&gt;alert(1)&lt;/script&gt;" in page
    assert not any(link.lower().startswith("javascript") for link in parsed.links)
    summary = next(k for k, row in enumerate(parsed.rows) if row and row[0] == "case")
    rows = parsed.rows[summary + 1:summary + 3]
    assert [row[0] for row in rows] == [PIPE, MARKUP]
    for row, case in zip(rows, results["cases"], strict=True):
        assert len(row) == 6
        assert float(row[1]) == pytest.approx(case["worst_linear_ratio"], rel=1e-3)
    assert "math" in parsed.tags and "img" in parsed.tags  # the report's own markup stays


def test_markdown_to_html_shows_html_as_text_and_keeps_formulas():
    from ins_errors.report import markdown_to_html

    page = markdown_to_html("# T\n\n<b>bold</b> & $x<y$\n\n<div>raw</div>\n\n"
                            "[a](java&#115;cript:alert(1)) [b](https://example.org/)\n", "T")
    parsed = _Page()
    parsed.feed(page)
    assert "b" not in parsed.tags and "div" not in parsed.tags and "math" in parsed.tags
    assert "&lt;b&gt;bold&lt;/b&gt; &amp;" in page
    assert parsed.links == ["#", "https://example.org/"]


@pytest.mark.parametrize("text", ["a | b", "a \\| b", "a\\\\|b|", "line\nbreak | x", "|"])
def test_table_cell_reads_back_as_the_text(text):
    from ins_errors.markdown_cells import table_cell
    from ins_errors.report import markdown_to_html

    row = f"| {table_cell(text)} | next |"
    shown = " ".join(text.split("\n")).strip()
    assert _cells(row) == [shown, "next"]
    page = _Page()  # and as the HTML report's converter reads it
    page.feed(markdown_to_html(f"| a | b |\n|---|---|\n{row}\n", "t"))
    assert page.rows[1] == [shown, "next"]
