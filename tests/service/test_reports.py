"""report.md and summary.csv of a job (issue 35): the final orientations themselves in the
``final_orientations`` column, and failed parts apart from those that cannot be oriented."""

from __future__ import annotations

import csv
import io
from typing import Any

from service.reports import report_markdown, summary_csv

GRIPPER = {"jaw_opening_mm": 12.0, "jaw_length_mm": 10.0, "push_distance_mm": None, "cycle_time_s": 2.5}
JOB = {"id": "f" * 32, "state": "done", "failed": 1, "cancelled": 0, "pending": 0}


def results() -> list[dict[str, Any]]:
    oriented = {"orientable": True, "action": "squeeze", "gripper": GRIPPER,
                "plan": {"steps": [{}, {}, {}], "final_orientations_deg": [70.0, 250.0], "final_uncertainty_deg": 0.25}}
    disk = {"orientable": False, "reasons": {"squeeze": "constant width"}}
    return [{"index": 0, "name": "pie", "status": "done", "result": oriented},
            {"index": 1, "name": "disk", "status": "done", "result": disk},
            {"index": 2, "name": "broken", "status": "failed", "result": None,
             "error": {"type": "part_document", "message": "open contour"}}]


def test_final_orientations_column_holds_the_orientations() -> None:
    rows = list(csv.DictReader(io.StringIO(summary_csv(results()))))
    assert rows[0]["final_orientations"] == "70.00°; 250.00° ± 0.25°"
    md = report_markdown(results(), JOB)
    pie_row = next(line for line in md.splitlines() if "| pie |" in line)
    assert "70.00°; 250.00° ± 0.25°" in pie_row and "| 2 |" not in pie_row


def test_failed_parts_are_not_listed_as_cannot_be_oriented() -> None:
    md = report_markdown(results(), JOB)
    cannot = md.split("## Parts that cannot be oriented")[1].split("## ")[0]
    assert "`disk`" in cannot and "constant width" in cannot
    assert "broken" not in cannot
    without = md.split("## Parts without a result")[1]
    assert "`broken`" in without and "open contour" in without
