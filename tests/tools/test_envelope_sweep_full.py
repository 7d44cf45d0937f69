"""The whole capability sweep (issue 8 part 3's "done when"): every one of the 135 grid points
inside the rated envelope holds on both inverter models, with the firmware defaults. Runs
tools/envelope_sweep.py --strict (exit 1 when a rated point does not hold) on the built dtc-sim
and reads its own CSV back: every row says it holds, with no fault, no runaway and the mean
speed within the 5 rpm of the criterion."""
import csv
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "tools" / "envelope_sweep.py"
SIM = Path(os.environ.get("DTC_SIM", REPO / "build" / "host" / "bin" / "dtc-sim"))


def test_every_rated_point_holds_on_both_inverters(tmp_path):
    assert SIM.is_file(), f"{SIM}: build the host preset first"
    out = tmp_path / "env"
    r = subprocess.run([sys.executable, str(SCRIPT), "--sim", str(SIM), "--out", str(out), "--inverter", "both",
                        "--strict", "--jobs", str(os.cpu_count() or 1)],
                       capture_output=True, text=True, timeout=600)
    print("\n".join(l for l in r.stdout.splitlines() if "points hold" in l or "fails:" in l or "wall time" in l))
    print(r.stderr[-3000:])
    assert r.returncode == 0, "a rated point does not hold (the lines starting 'fails:' above)"
    for inverter in ("real", "ideal"):
        with open(out / inverter / "results.csv", newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
        assert len(rows) == 135, inverter
        for row in rows:
            where = f"{inverter} {row['name']}"
            assert row["holds"] == "True", where
            assert int(row["faults"]) == 0 and row["runaway"] == "False", where
            assert abs(float(row["speed_rpm"]) - float(row["rpm"])) <= 5.0, where
