#!/usr/bin/python3
"""report.key_cards names the origin of the peak gauge velocity's time: the earthquake's start
once dr2_postprocess.py has rewritten the gauges (it keeps the runner's as
gauges_from_run_start), the run's start otherwise. Exits 1 with the card it got otherwise."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "scripts"))
import report  # noqa: E402

gauge = {"name": "gauge1", "max_displacement_m": 120.0, "peak_velocity_mps": 21.0, "time_of_peak_velocity_s": 12.5}
failed = False
for summary, want in (({"gauges": [gauge]}, "at 12.5 s from the run's start"),
                      ({"gauges": [gauge], "gauges_from_run_start": [gauge], "earthquake_start_s": 25.3},
                       "at 12.5 s from the earthquake's start")):
    html = report.key_cards(summary)
    if want not in html.replace("&#x27;", "'"):
        print("key_cards:", html, "\nexpected the text:", want)
        failed = True
sys.exit(1 if failed else 0)
