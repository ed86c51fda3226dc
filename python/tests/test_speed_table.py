"""benches/speed_table.py's rendering: the figures as docs/speed.md's test reads them."""

import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "benches"))
import speed_table  # noqa: E402


def test_times_have_three_significant_figures_in_the_unit_that_keeps_them_below_a_thousand():
    cases = {4.684: "4.68 ns", 44.63: "44.6 ns", 99.96: "100 ns", 315.2: "315 ns",
             999.6: "1.00 µs", 1110.0: "1.11 µs", 30412.0: "30.4 µs", 52.1e6: "52.1 ms",
             2.7e9: "2.70 s"}
    for ns, text in cases.items():
        assert speed_table.time_text(ns) == text


def test_a_rendered_run_holds_every_row_ratio_and_target_between_the_markers():
    rows = {slow: {"median_ns": 1000.0, "mad_ns": 10.0} for _, slow, _, _ in speed_table.RATIOS}
    rows |= {fast: {"median_ns": 100.0, "mad_ns": 1.0} for _, _, fast, _ in speed_table.RATIOS}
    rows["inverse_dynamics/generated_consistent_batch_x4"] = {"median_ns": 180.0, "mad_ns": 1.0}
    for _, _, key, sense, _ in speed_table.TARGETS:
        if sense == "<=":
            rows[key] = {"median_ns": 200.0, "mad_ns": 2.0}
    run = {"date": "2026-11-27 00:00", "core": 0, "host": "a host", "pinocchio": "4.1.0",
           "load": [0.1, 0.2], "rows": rows}
    run["ratios"] = speed_table.ratios(rows)
    table = speed_table.render(run)
    assert table.startswith(speed_table.BEGIN) and table.endswith(speed_table.END)
    for name in rows:
        assert f"| `{name}` |" in table
    # A batch's per-state column, a ratio per state, a target met and one missed.
    assert "| `inverse_dynamics/generated_consistent_batch_x4` | 180 ns | ±0.6 % | 45.0 ns |" in table
    assert "| C5 inverse dynamics, batch of four against single (throughput) | 2.22× |" in table
    assert "| 40 | hexapod inverse dynamics (folded) ≤ 150 ns | 200 ns | **missed** |" in table
    assert "| 38 | Delta forward dynamics against Pinocchio C++ ≥ 30.0× | 10.0× | **missed** |" in table


def test_the_page_holds_the_table_its_recorded_run_renders():
    """docs/speed.md's table is docs/speed-run.json rendered, not edited by hand."""
    run = json.loads(speed_table.RUN.read_text())
    run["ratios"] = speed_table.ratios(run["rows"])
    page = speed_table.PAGE.read_text()
    start, end = speed_table.table_span(page)
    assert page[start:end] == speed_table.render(run)
