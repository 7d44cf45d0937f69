#!/usr/bin/env python3
"""Print the paper-case metrics of several dtc-sim runs side by side.

Usage: metrics_table.py RUN.json [RUN.json ...]
Each file is a `dtc-sim run --metrics` output. Rows are the issue's metrics; the
last column checks RBFN against IP (recovery at least 3x faster).
"""
import json
import math
import sys

ROWS = [
    ("recovery_time_s", "recovery time after the disturbance", "s", "{:.3f}"),
    ("max_dip_rpm", "largest speed error after it", "rpm", "{:.1f}"),
    ("steady_error_rpm", "mean |error|, last 0.5 s", "rpm", "{:.2f}"),
    ("speed_est_error_rpm", "mean |estimate - true|, last 0.5 s", "rpm", "{:.2f}"),
    ("eps_hat_final", "RBFN uncertainty estimate", "rad/s^2", "{:.1f}"),
    ("eps_true", "true uncertainty (eq. 5)", "rad/s^2", "{:.1f}"),
    ("w_norm_max", "largest |W|", "", "{:.1f}"),
    ("m_w", "projection bound M_w", "", "{:.1f}"),
    ("np_dev_max_v", "largest |vc1 - vc2|", "V", "{:.2f}"),
    ("switching_freq_hz", "device switching frequency", "Hz", "{:.0f}"),
    ("speed_final_rpm", "final speed", "rpm", "{:.1f}"),
    ("wall_seconds", "wall time of the run", "s", "{:.2f}"),
]


RBFN_ONLY = {"eps_hat_final", "w_norm_max", "m_w"}


def cell(run, key, pattern):
    """One table cell: '-' where the metric does not apply to this run."""
    value = run.get(key)
    if key in RBFN_ONLY and run.get("controller") != "rbfn":
        return "-"
    if key == "recovery_time_s" and run.get("recovered") is False:
        return "never"
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "-"
    return pattern.format(value)


def main(paths):
    runs = []
    for p in paths:
        try:
            with open(p, encoding="utf-8") as f:
                runs.append(json.load(f))
        except (OSError, ValueError) as e:
            print(f"metrics_table: {p}: {e}", file=sys.stderr)
            return 2
    names = [r.get("controller", p) for r, p in zip(runs, paths)]
    width = 38
    print(f"{'metric':<{width}}{'unit':<9}" + "".join(f"{n:>11}" for n in names))
    print("-" * (width + 9 + 11 * len(names)))
    for key, label, unit, pattern in ROWS:
        cells = "".join(f"{cell(r, key, pattern):>11}" for r in runs)
        print(f"{label:<{width}}{unit:<9}{cells}")
    by = dict(zip(names, runs))
    if "ip" in by and "rbfn" in by:
        ip_rec, rb_rec = by["ip"].get("recovery_time_s"), by["rbfn"].get("recovery_time_s")
        if ip_rec and rb_rec and by["ip"].get("recovered", True) and by["rbfn"].get("recovered", True):
            print(f"\nIP recovery / RBFN recovery = {ip_rec / rb_rec:.1f}x (paper: about 7x in simulation)")
    return 0


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1:]))
