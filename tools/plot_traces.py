#!/usr/bin/env python3
"""Plot dtc-sim CSV traces as the paper's Fig. 5 / Fig. 6: one column per speed controller
(IP beside RBFN), one row per signal: speed, speed error, phase current, control input (torque
command), observed uncertainty.

  plot_traces.py --ip ip.csv --rbfn rbfn.csv --out fig.png            # Fig. 6 (CASE2), 5 panels
  plot_traces.py --ip ip.csv --rbfn rbfn.csv --panels speed,current,torque --out fig5.png  # Fig. 5
  plot_traces.py --run "nominal=nom.csv" --rbfn rbfn.csv --out fig.png  # any runs, any labels

Columns used (dtc-sim trace, see docs/scenarios.md): t_s, speed_rpm, speed_ref_rpm (or
ref_cmd_rpm), speed_est_rpm, speed_err_true_rpm, ia_a, te_ref_nm, eps_hat, eps_true, t_load_nm.
A vertical dotted line marks the disturbance (first change of t_load_nm) unless --event is given.
Errors: exit status 2 and one line.
"""
from __future__ import annotations

import argparse
import csv
import math
import os
import sys
from typing import Dict, List, Optional, Tuple

PANELS = {
    # key: (title, y label, [(column, style, label)], required columns)
    "speed": ("speed", "rpm", [("speed_ref_rpm", "k--", "reference"), ("speed_rpm", "C0-", "true"),
                               ("speed_est_rpm", "C1:", "estimated")], ["speed_rpm"]),
    "error": ("speed error", "rpm", [("speed_err_true_rpm", "C0-", "reference - true")], ["speed_err_true_rpm"]),
    "current": ("phase current", "A", [("ia_a", "C0-", "i_a")], ["ia_a"]),
    "torque": ("control input (torque command)", "N m", [("te_ref_nm", "C0-", "T_e*")], ["te_ref_nm"]),
    "eps": ("observed uncertainty", "rad/s$^2$", [("eps_true", "--", "true (eq. 5)"),
                                                  ("eps_hat", "C3-", "RBFN estimate")], []),
}
DEFAULT_PANELS = "speed,error,current,torque,eps"


class PlotError(Exception):
    pass


def read_trace(path: str) -> Dict[str, List[float]]:
    """Columns of a dtc-sim CSV as float lists (empty cells: NaN)."""
    try:
        with open(path, newline="") as f:
            reader = csv.reader(f)
            try:
                header = [h.strip() for h in next(reader)]
            except StopIteration:
                raise PlotError("%s: empty file" % path) from None
            cols: Dict[str, List[float]] = {h: [] for h in header}
            for lineno, row in enumerate(reader, start=2):
                if not row:
                    continue
                if len(row) != len(header):
                    raise PlotError("%s:%d: %d fields, the header has %d" % (path, lineno, len(row), len(header)))
                for h, cell in zip(header, row):
                    cell = cell.strip()
                    try:
                        cols[h].append(float(cell) if cell else math.nan)
                    except ValueError:
                        raise PlotError("%s:%d: column %s: '%s' is not a number" % (path, lineno, h, cell)) from None
    except OSError as e:
        raise PlotError("%s: %s" % (path, e.strerror or e)) from None
    if "t_s" not in cols:
        raise PlotError("%s: no t_s column (is this a dtc-sim trace?)" % path)
    if not cols["t_s"]:
        raise PlotError("%s: no data rows" % path)
    if "speed_ref_rpm" in cols and all(math.isnan(v) for v in cols["speed_ref_rpm"]) and "ref_cmd_rpm" in cols:
        cols["speed_ref_rpm"] = cols["ref_cmd_rpm"]
    elif "speed_ref_rpm" not in cols and "ref_cmd_rpm" in cols:
        cols["speed_ref_rpm"] = cols["ref_cmd_rpm"]
    return cols


def disturbance_time(cols: Dict[str, List[float]]) -> Optional[float]:
    load = cols.get("t_load_nm")
    if not load:
        return None
    first = load[0]
    for t, v in zip(cols["t_s"], load):
        if not math.isnan(v) and abs(v - first) > 1e-9:
            return t
    return None


def parse_runs(args) -> List[Tuple[str, str]]:
    runs: List[Tuple[str, str]] = []
    if args.ip:
        runs.append(("IP control", args.ip))
    if args.nominal:
        runs.append(("nominal control", args.nominal))
    if args.rbfn:
        runs.append(("RBFN control (proposed)", args.rbfn))
    for spec in args.run or []:
        if "=" not in spec:
            raise PlotError("--run needs LABEL=CSV, got '%s'" % spec)
        label, path = spec.split("=", 1)
        runs.append((label, path))
    if not runs:
        raise PlotError("nothing to plot: give --ip, --rbfn, --nominal or --run LABEL=CSV")
    return runs


def plot(runs, panels: List[str], out: str, title: Optional[str], t_range, event: Optional[float]) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = [(label, read_trace(path), path) for label, path in runs]
    for key in panels:
        for label, cols, path in data:
            missing = [c for c in PANELS[key][3] if c not in cols]
            if missing:
                raise PlotError("%s: panel '%s' needs column %s" % (path, key, ", ".join(missing)))

    n_rows, n_cols = len(panels), len(data)
    fig, axes = plt.subplots(n_rows, n_cols, figsize=(4.8 * n_cols + 0.6, 1.9 * n_rows + 0.9),
                             sharex=True, squeeze=False)
    for j, (label, cols, _path) in enumerate(data):
        t = cols["t_s"]
        t_event = event if event is not None else disturbance_time(cols)
        for i, key in enumerate(panels):
            ax = axes[i][j]
            ptitle, ylabel, series, _ = PANELS[key]
            drawn = False
            for col, style, slabel in series:
                y = cols.get(col)
                if y is None or all(math.isnan(v) for v in y):
                    continue
                if key == "eps" and col == "eps_hat" and "rbfn" not in label.lower() and \
                        max((abs(v) for v in y if not math.isnan(v)), default=0.0) == 0.0:
                    continue  # IP / nominal: no observer, nothing to show
                lw = 0.5 if col in ("ia_a", "eps_true") else 0.9
                extra = {"color": "0.55"} if col == "eps_true" else {}  # noisy (instantaneous torque): keep it light
                ax.plot(t, y, style, lw=lw, label=slabel, **extra)
                drawn = True
            if t_event is not None:
                ax.axvline(t_event, color="0.5", ls=":", lw=0.8)
            if i == 0:
                ax.set_title(label, fontsize=10)
            if j == 0:
                ax.set_ylabel("%s\n[%s]" % (ptitle, ylabel), fontsize=8)
            ax.grid(True, lw=0.3)
            ax.tick_params(labelsize=7)
            if drawn and len(series) > 1:
                ax.legend(fontsize=6, loc="best")
            if not drawn:
                ax.text(0.5, 0.5, "not available", transform=ax.transAxes, ha="center", va="center",
                        fontsize=8, color="0.4")
        axes[-1][j].set_xlabel("time [s]", fontsize=8)
        if t_range:
            axes[-1][j].set_xlim(*t_range)
    # Same y range across a row so the controllers compare at a glance.
    for i in range(n_rows):
        lims = [axes[i][j].get_ylim() for j in range(n_cols)]
        lo, hi = min(l[0] for l in lims), max(l[1] for l in lims)
        for j in range(n_cols):
            axes[i][j].set_ylim(lo, hi)
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    tmp = out + ".partial.png"
    try:
        fig.savefig(tmp, dpi=130)
        os.replace(tmp, out)
    except OSError as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise PlotError("cannot write %s: %s" % (out, e.strerror or e)) from None
    finally:
        plt.close(fig)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ip", help="trace of the IP controller run")
    ap.add_argument("--nominal", help="trace of the nominal controller run")
    ap.add_argument("--rbfn", help="trace of the RBFN controller run")
    ap.add_argument("--run", action="append", metavar="LABEL=CSV", help="another run (repeatable)")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--panels", default=DEFAULT_PANELS,
                    help="comma-separated rows among %s (default: all, as Fig. 6)" % ",".join(PANELS))
    ap.add_argument("--title", default=None)
    ap.add_argument("--tmin", type=float, default=None)
    ap.add_argument("--tmax", type=float, default=None)
    ap.add_argument("--event", type=float, default=None, help="time of the disturbance line, s")
    try:
        args = ap.parse_args(argv)
    except SystemExit as e:
        return int(e.code or 0) if e.code in (0, None) else 2
    try:
        panels = [p.strip() for p in args.panels.split(",") if p.strip()]
        bad = [p for p in panels if p not in PANELS]
        if bad or not panels:
            raise PlotError("unknown panel %s (choose from %s)" % (", ".join(bad) or "''", ", ".join(PANELS)))
        t_range = None
        if args.tmin is not None or args.tmax is not None:
            t_range = (args.tmin, args.tmax)
        plot(parse_runs(args), panels, args.out, args.title, t_range, args.event)
    except PlotError as e:
        print("plot_traces: error: %s" % e, file=sys.stderr)
        return 2
    print("plot_traces: wrote %s" % args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
