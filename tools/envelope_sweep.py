#!/usr/bin/env python3
"""Capability sweep of the drive over its torque-speed plane.

One scenario file per grid point is written into OUT/<inverter>/points/ (so a
point can be re-run by hand with `dtc-sim run FILE`), every point is run with
`dtc-sim run --metrics` in a process pool, and the results are printed as a
table, written as results.csv / results.json and drawn as a datasheet-style
capability map (OUT/capability.png).

Grid (default): speeds 0 and +-{30, 300, 870, 1740, 2200, 2610} rpm x torque
fractions {0, 0.25, 0.5, 0.75, 1} of the rated torque limit at that speed
(41 N m up to base speed, 7457 W / omega above), each non-zero torque both
motoring (the load opposes the rotation) and generating (an active load
drives the rotation; at 0 rpm: the two directions of the load): 13 x (1 + 4 x 2)
= 117 points. Each point's stator frequency (rotor plus slip, from the motor's
parameters) is reported: within 1 Hz of zero a sensorless drive cannot hold a
loaded point in steady state (not observable), and failures there say so.

Each point: ramp 0 -> speed, load step once the speed has settled, mean
speed over a late window, NP deviation and switching frequency from half a
second after the load step to the end, stator rms current over the window.
A point HOLDS when no fault latched, the true speed never ran away, and the
window's mean speed is within the tolerance of the reference.

Usage: envelope_sweep.py [--out DIR] [--jobs N] [--inverter real|ideal|both]
                         [--speeds LIST] [--fractions LIST] [--extra RPM:NM ...]
                         [--tol-rpm RPM] [--docs-png PATH] [--strict]
"""
import argparse
import csv
import datetime
import json
import math
import multiprocessing
import os
import re
import shutil
import subprocess
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# The 10 hp motor's nameplate (docs/motor-10hp.json, docs/envelope.md section 3).
BASE_RPM = 1740.0
RATED_NM = 41.0
RATED_W = 7457.0
MAX_RPM = 2610.0  # 1.5 x base speed, the end of the constant-power range
# Firmware defaults that set the drive's own (peak) torque limit (ctl.c, speed_ctl.c):
TE_MAX_NM = 80.0          # speed.te_max_Nm
FW_VOLTAGE_FRAC = 0.9     # fw_voltage_frac
TE_PULLOUT_FRAC = 0.9     # te_pullout_frac
PSI_RATED_WB = 0.45       # dtc.psi_ref_Wb
PULLOUT_NM_PER_WB2 = 502.0  # 1.5 p (1 - sigma) / (2 sigma Ls) of the 10 hp motor
VDC_V = 311.0
POLE_PAIRS = 2
NP_LIMIT_V = 0.02 * VDC_V  # 2 % of Vdc, the neutral-point figure (not a trip)

DEFAULT_SPEEDS = [0, 30, 100, 300, 870, 1740, 2200, 2610, -30, -100, -300, -870, -1740, -2200, -2610]
DEFAULT_FRACTIONS = [0.0, 0.25, 0.5, 0.75, 1.0]
# Speed tolerance of "holds": the low-speed figure (30 rpm / 41 N m "within 5 rpm",
# docs/envelope.md section 6), applied everywhere; 2 % of base speed (34.8 rpm) would pass
# a 30 rpm point that runs at 19 rpm.
TOL_RPM = 5.0

# Timing of one point (s): reference ramp at RAMP_RPM_S (below the firmware's own slew
# limit of 100 rad/s^2 = 955 rpm/s), load SETTLE_S after the ramp, NP and switching
# from NP_DELAY_S after the load, the speed/current window the last WINDOW_S. 10 s loaded:
# near zero stator frequency a generating point drifts for seconds (2.5 s hid a drift of
# +-30 rpm with 20.5 N m generating to 37-41 rpm by 12 s).
T_RAMP0 = 0.3
RAMP_RPM_S = 800.0
SETTLE_S = 0.7
NP_DELAY_S = 0.5
LOADED_S = 10.0
WINDOW_S = 1.0

FAULT_NAMES = ["OVERCURRENT", "DC_OVERVOLT", "DC_UNDERVOLT", "NP_IMBALANCE", "OVERSPEED",
               "STALE_SAMPLE", "HW", "OVERRUN", "SAMPLE_INVALID", "LOSS_OF_CONTROL",
               "CURRENT_SENSOR", "PHASE_LOSS", "DC_DIVIDER"]

INVERTERS = {
    # The plant's default: 2 us dead time, 1 V per device; the firmware's default
    # v_drop_V = 1 compensates the drops. Nothing to set.
    "real": "",
    # The ideal inverter of the paper's case files.
    "ideal": "\n[inverter]\ndead_time_s = 0\nv_on_V = 0\n\n[control]\nv_drop_V = 0\n",
}


# Steady-state slip of the 10 hp motor (host_sim/plant/src/plant_config.c: Rr 0.158 ohm,
# Lm 41.6 mH, Lr = Ls 43.02 mH): with the rotor flux psi_r, omega_slip = (2/3) Rr Te / (p psi_r^2)
# (rotor-flux orientation), psi_r = psi_s Lm / Ls at the rated stator flux (or the
# field-weakening flux above base speed).
RR_OHM = 0.158
LM_OVER_LS = 0.0416 / 0.04302
# Within this stator frequency of zero an induction machine is not observable from its
# terminals in steady state (the rotor's EMF vanishes from the stator equations): a
# sensorless drive can pass through but not hold such a point. Points there are reported
# as such; they still count as failures when they fail.
ZERO_FS_HZ = 1.0


def stator_frequency_hz(rpm, load_nm):
    """Stator frequency of a point, Hz: rotor (electrical) plus slip. load_nm is the [load]
    step (a torque opposing positive speed): the motor's torque is +load_nm in steady state."""
    w_r = POLE_PAIRS * rpm * math.pi / 30.0
    psi_s = PSI_RATED_WB if w_r == 0 else min(PSI_RATED_WB, FW_VOLTAGE_FRAC * VDC_V / math.sqrt(3) / abs(w_r))
    psi_r = psi_s * LM_OVER_LS
    w_slip = 2.0 / 3.0 * RR_OHM * load_nm / (POLE_PAIRS * psi_r * psi_r)
    return (w_r + w_slip) / (2.0 * math.pi)


def rated_torque(rpm):
    """The rated envelope: 41 N m up to base speed, constant power above."""
    n = abs(rpm)
    if n <= BASE_RPM:
        return RATED_NM
    return RATED_W / (n * math.pi / 30.0)


def drive_torque_limit(rpm):
    """The firmware's own torque limit at the default settings (no trim, nominal link):
    min(te_max, te_pullout_frac x pull-out torque at the field-weakening flux)."""
    w_e = POLE_PAIRS * abs(rpm) * math.pi / 30.0
    psi = PSI_RATED_WB if w_e == 0 else min(PSI_RATED_WB, FW_VOLTAGE_FRAC * VDC_V / math.sqrt(3) / w_e)
    return min(TE_MAX_NM, TE_PULLOUT_FRAC * PULLOUT_NM_PER_WB2 * psi * psi)


def point_name(p):
    sign = "p" if p["rpm"] >= 0 else "m"
    return f"{sign}{abs(p['rpm']):04.0f}_{p['mode']}_{p['load_nm_abs']:05.1f}Nm".replace(".", "p")


def make_points(speeds, fractions, extras):
    """The grid, then the extra points (RPM, |N m| motoring)."""
    pts = []
    for rpm in speeds:
        for frac in fractions:
            modes = ["noload"] if frac == 0 else ["motoring", "generating"]
            for mode in modes:
                # rounded down to 0.01 N m: a point at 1 x never lies beyond the limit
                pts.append({"rpm": float(rpm), "frac": frac, "mode": mode,
                            "load_nm_abs": math.floor(frac * rated_torque(rpm) * 100 + 1e-6) / 100})
    for rpm, nm in extras:
        pts.append({"rpm": float(rpm), "frac": round(nm / rated_torque(rpm), 3),
                    "mode": "motoring" if nm >= 0 else "generating", "load_nm_abs": abs(nm)})
    for p in pts:
        # [load] step is a torque opposing POSITIVE speed that keeps its sign at negative
        # speed: motoring (opposing the rotation) has the sign of the speed, generating
        # (driving the rotation) the opposite sign.
        s = 1.0 if p["rpm"] >= 0 else -1.0
        p["load_nm"] = {"noload": 0.0, "motoring": s, "generating": -s}[p["mode"]] * p["load_nm_abs"]
        p["name"] = point_name(p)
    return pts


def scenario_text(p, inverter):
    rpm = p["rpm"]
    t_ramp1 = T_RAMP0 + max(0.2, abs(rpm) / RAMP_RPM_S)
    t_load = round(t_ramp1 + SETTLE_S, 3)
    t_end = round(t_load + LOADED_S, 3)
    p.update(t_load=t_load, t_end=t_end)
    return (f"# Capability sweep point (tools/envelope_sweep.py): {rpm:+.0f} rpm, {p['mode']}, "
            f"{p['load_nm_abs']:.2f} N m ({p['frac']:.2f} x the rated torque at this speed).\n"
            f"# Re-run: build/host/bin/dtc-sim run THIS_FILE --metrics out.json --csv out.csv\n"
            f"[sim]\nduration_s = {t_end}\n\n[controller]\nname = rbfn\n\n"
            f"[reference]\nramp = {T_RAMP0} {t_ramp1:.3f} {rpm:.0f}\n\n"
            f"[load]\nstep = {t_load} {p['load_nm']:.2f}\n\n"
            f"[metrics]\ndisturbance_t_s = {t_load}\nstartup_end_s = {round(t_load + NP_DELAY_S, 3)}\n"
            f"window = point {round(t_end - WINDOW_S, 3)} {t_end}\n" + INVERTERS[inverter])


def run_point(job):
    """Worker: run one scenario, return the point with its parsed metrics."""
    sim, p = job
    t0 = time.monotonic()
    r = subprocess.run([sim, "run", p["ini"], "--metrics", p["json"]],
                       capture_output=True, text=True)
    p = dict(p, exit=r.returncode, wall=time.monotonic() - t0)
    if r.returncode != 0:
        p["error"] = (r.stderr.strip().splitlines() or ["exit %d" % r.returncode])[-1]
        return p
    with open(p["json"], encoding="utf-8") as f:
        p["metrics"] = json.load(f)
    return p


def judge(p, tol):
    """Fill in the table's figures and the verdict."""
    m = p.get("metrics")
    if m is None:
        p.update(holds=False, cause="sim error: " + p.get("error", "?"))
        return p
    speed = m.get("window_point_speed_rpm", float("nan"))
    p["speed_rpm"] = speed
    p["err_rpm"] = speed - p["rpm"]
    p["steady_err_rpm"] = m.get("steady_error_rpm", float("nan"))
    p["np_v"] = m.get("np_dev_max_v", float("nan"))
    p["fsw_hz"] = m.get("switching_freq_hz", float("nan"))
    p["is_rms_a"] = m.get("window_point_is_rms_a", float("nan"))
    p["te_nm"] = m.get("te_final_nm", float("nan"))
    p["faults"] = int(m.get("faults", 0))
    p["runaway"] = bool(m.get("runaway", False))
    causes = [n for i, n in enumerate(FAULT_NAMES) if p["faults"] >> i & 1]
    if p["faults"] >> len(FAULT_NAMES):
        causes.append("fault 0x%x" % p["faults"])
    if p["runaway"]:
        causes.append("runaway (|n| up to %.0f rpm, %.0f at the end)"
                      % (m.get("speed_true_max_abs_rpm", float("nan")), m.get("speed_true_end_rpm", float("nan"))))
    if not causes and not abs(p["err_rpm"]) <= tol:  # NaN fails too
        causes.append("speed error %+.1f rpm" % p["err_rpm"])
    p["fs_hz"] = stator_frequency_hz(p["rpm"], p["load_nm"])
    p["zero_fs"] = abs(p["fs_hz"]) < ZERO_FS_HZ and p["load_nm"] != 0.0
    if causes and p["zero_fs"]:
        causes.append("at f_s %+.2f Hz (zero stator frequency)" % p["fs_hz"])
    p["holds"] = not causes
    p["cause"] = ", ".join(causes)
    return p


def fmt(v, pattern):
    return "-" if v is None or (isinstance(v, float) and math.isnan(v)) else pattern.format(v)


def print_table(pts, title):
    print(title)
    head = (f"{'speed':>7} {'mode':<10} {'load':>7} {'x rated':>7} {'mean n':>8} {'error':>7} "
            f"{'|err|':>6} {'NP max':>6} {'f_sw':>5} {'Is rms':>6} {'faults':>7}  result")
    units = (f"{'rpm':>7} {'':<10} {'N m':>7} {'':>7} {'rpm':>8} {'rpm':>7} "
             f"{'rpm':>6} {'V':>6} {'Hz':>5} {'A':>6} {'':>7}")
    print(head)
    print(units)
    print("-" * len(head))
    for p in pts:
        res = "holds" if p["holds"] else "FAILS " + p["cause"]
        if p["holds"] and p.get("np_v", 0) > NP_LIMIT_V:
            res += " (NP > 2 %)"
        print(f"{p['rpm']:>7.0f} {p['mode']:<10} {p['load_nm']:>7.2f} {p['frac']:>7.2f} "
              f"{fmt(p.get('speed_rpm'), '{:.1f}'):>8} {fmt(p.get('err_rpm'), '{:+.2f}'):>7} "
              f"{fmt(p.get('steady_err_rpm'), '{:.2f}'):>6} {fmt(p.get('np_v'), '{:.2f}'):>6} "
              f"{fmt(p.get('fsw_hz'), '{:.0f}'):>5} {fmt(p.get('is_rms_a'), '{:.1f}'):>6} "
              f"{fmt(p.get('faults'), '0x{:03x}'):>7}  {res}")


def write_results(pts, out):
    cols = ["name", "rpm", "mode", "frac", "load_nm", "fs_hz", "speed_rpm", "err_rpm", "steady_err_rpm",
            "np_v", "fsw_hz", "is_rms_a", "te_nm", "faults", "runaway", "holds", "cause", "ini"]
    with open(os.path.join(out, "results.csv"), "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        for p in pts:
            w.writerow({k: p.get(k, "") for k in cols})
    with open(os.path.join(out, "results.json"), "w", encoding="utf-8") as f:
        json.dump([{k: v for k, v in p.items() if k != "metrics"} for p in pts], f, indent=1)


def cause_kind(cause):
    """The first cause without its figures: 'LOSS_OF_CONTROL', 'runaway', 'speed error'."""
    m = re.match(r"[A-Za-z_ ]+", cause.split(",")[0])
    return m.group(0).strip() if m else cause


def draw_map(sets, path, tol, date):
    """Datasheet-style torque-speed plane, one column per inverter model: the whole
    range above, a zoom on the low speeds below (the +-30 rpm points sit on the axis)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    ncol = len(sets)
    fig, axes = plt.subplots(2, ncol, figsize=(8.0 * ncol, 11.5), squeeze=False,
                             gridspec_kw={"height_ratios": [3, 2]})
    n = np.linspace(-MAX_RPM * 1.15, MAX_RPM * 1.15, 2001)
    rated = np.array([rated_torque(x) if abs(x) <= MAX_RPM else np.nan for x in n])
    peak = np.array([drive_torque_limit(x) for x in n])
    markers = {"LOSS_OF_CONTROL": "X", "OVERSPEED": "P", "NP_IMBALANCE": "D", "OVERCURRENT": "*",
               "runaway": "^", "speed error": "v"}
    handles = {}
    for col, (inv, pts) in enumerate(sets):
        for row in (0, 1):
            ax = axes[row][col]
            h = ax.fill_between(n, -rated, rated, color="#dbe9f6", zorder=0)
            handles.setdefault("rated envelope: 41 N m up to 1740 rpm, 7457 W above (to 2610 rpm)", h)
            ax.plot(n, rated, color="#1f4e79", lw=1.8, zorder=1)
            ax.plot(n, -rated, color="#1f4e79", lw=1.8, zorder=1)
            (h,) = ax.plot(n, peak, color="#7f7f7f", lw=1.2, ls="--", zorder=1)
            handles.setdefault("drive's own torque limit, firmware defaults "
                               "(te_max 80 N m; 0.9 x pull-out torque in field weakening)", h)
            ax.plot(n, -peak, color="#7f7f7f", lw=1.2, ls="--", zorder=1)
            for x in (-BASE_RPM, BASE_RPM):
                ax.axvline(x, color="#1f4e79", lw=0.6, ls=":", zorder=1)
            ax.axhline(0, color="black", lw=0.6)
            ax.axvline(0, color="black", lw=0.6)
            # Quadrants: motoring where torque and speed have the same sign.
            for (qx, qy, txt) in ((0.98, 0.97, "I  motoring"), (0.02, 0.97, "II  generating"),
                                  (0.02, 0.03, "III  motoring"), (0.98, 0.03, "IV  generating")):
                ax.text(qx, qy, txt, transform=ax.transAxes, ha="right" if qx > 0.5 else "left",
                        va="top" if qy > 0.5 else "bottom", fontsize=9, color="#555555")
            for p in pts:
                te = p["load_nm"]  # in steady state the motor's torque balances the load
                if p["holds"]:
                    np_ok = not p.get("np_v", 0) > NP_LIMIT_V
                    lab = "holds" if np_ok else "holds; NP deviation above 2 % of Vdc (no trip)"
                    h = ax.scatter(p["rpm"], te, s=46, marker="o", zorder=3,
                                   facecolor="#2ca02c" if np_ok else "white", edgecolor="#2ca02c",
                                   linewidth=1.6)
                else:
                    kind = cause_kind(p["cause"])
                    lab = "fails: " + kind
                    h = ax.scatter(p["rpm"], te, s=80, marker=markers.get(kind, "s"), zorder=4,
                                   color="#d62728")
                    if row == 1:
                        err = p.get("err_rpm")
                        txt = ("%+.0f rpm" % err) if kind == "speed error" else kind.replace("_", " ").lower()
                        ax.annotate(txt, (p["rpm"], te), textcoords="offset points",
                                    xytext=(7 if p["rpm"] > 0 else -7, 4), fontsize=7.5, color="#d62728",
                                    ha="left" if p["rpm"] > 0 else "right")
                handles.setdefault(lab, h)
            ax.set_xlabel("speed (rpm, mechanical)")
            ax.set_ylabel("shaft torque (N m)")
            ax.grid(True, color="#e0e0e0", lw=0.5)
            ax.set_ylim(-TE_MAX_NM * 1.1, TE_MAX_NM * 1.1)
            if row == 0:
                n_hold = sum(p["holds"] for p in pts)
                ax.set_xlim(-MAX_RPM * 1.15, MAX_RPM * 1.15)
                ax.set_title(f"{inv} inverter" + (" (plant default: 2 us dead time, 1 V per device)"
                                                  if inv == "real" else " (no dead time, no drops)")
                             + f": {n_hold} of {len(pts)} points hold", fontsize=10.5)
            else:
                ax.set_xlim(-420, 420)
                ax.set_ylim(-56, 56)
                ax.set_title("low speeds (zoom)", fontsize=10)
    order = sorted(handles, key=lambda k: (not k.startswith("rated"), not k.startswith("drive"),
                                           not k.startswith("holds"), k))
    fig.legend([handles[k] for k in order], order, loc="lower center", ncol=2, fontsize=8.5,
               frameon=False)
    fig.suptitle("10 hp sensorless three-level NPC DTC drive, RBFN speed controller, firmware defaults: "
                 "capability map (SIL)\n"
                 f"311 V link; holds = no fault, no runaway, mean speed within {tol:.1f} rpm of the "
                 f"reference over the last {WINDOW_S:.0f} s; {date}", fontsize=11)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    fig.savefig(path, dpi=100)
    plt.close(fig)


def parse_list(s):
    return [float(x) for x in s.split(",") if x.strip()]


def parse_extra(s):
    rpm, nm = s.split(":")
    return float(rpm), float(nm)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(REPO, "out", "envelope"))
    ap.add_argument("--sim", default=os.path.join(REPO, "build", "host", "bin", "dtc-sim"))
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--inverter", choices=["real", "ideal", "both"], default="real")
    ap.add_argument("--speeds", type=parse_list, default=DEFAULT_SPEEDS, help="rpm, comma separated")
    ap.add_argument("--fractions", type=parse_list, default=DEFAULT_FRACTIONS,
                    help="fractions of the rated torque at each speed, comma separated")
    ap.add_argument("--extra", type=parse_extra, action="append", default=[],
                    metavar="RPM:NM", help="an extra point, e.g. 870:100 (a motoring load of 100 N m)")
    ap.add_argument("--tol-rpm", type=float, default=TOL_RPM)
    ap.add_argument("--docs-png", default="", help="also copy the map here")
    ap.add_argument("--strict", action="store_true",
                    help="exit status 1 when a point inside the rated envelope does not hold")
    a = ap.parse_args(argv)

    t_start = time.monotonic()
    if not os.access(a.sim, os.X_OK):
        print(f"envelope_sweep: {a.sim}: not built (cmake --preset host && cmake --build --preset host)",
              file=sys.stderr)
        return 2
    inverters = ["real", "ideal"] if a.inverter == "both" else [a.inverter]
    os.makedirs(a.out, exist_ok=True)
    jobs, sets, n_inside_fail = [], [], 0
    for inv in inverters:
        pdir = os.path.join(a.out, inv, "points")
        if os.path.isdir(pdir):
            shutil.rmtree(pdir)  # no stale points of an earlier, different grid
        os.makedirs(pdir)
        pts = make_points(a.speeds, a.fractions, a.extra)
        for p in pts:
            p["inverter"] = inv
            p["ini"] = os.path.join(pdir, p["name"] + ".ini")
            p["json"] = os.path.join(pdir, p["name"] + ".json")
            with open(p["ini"], "w", encoding="utf-8") as f:
                f.write(scenario_text(p, inv))
            jobs.append((a.sim, p))
    with multiprocessing.Pool(max(1, a.jobs)) as pool:
        done = pool.map(run_point, jobs, chunksize=1)
    cpu = sum(p["wall"] for p in done)
    for inv in inverters:
        pts = [judge(p, a.tol_rpm) for p in done if p["inverter"] == inv]
        sets.append((inv, pts))
        n_hold = sum(p["holds"] for p in pts)
        print_table(pts, f"\nCapability sweep, {inv} inverter ({'plant default: 2 us dead time, 1 V per device' if inv == 'real' else 'no dead time, no drops'}); "
                         f"holds = no fault, no runaway, |mean speed - reference| <= {a.tol_rpm:.1f} rpm over the last {WINDOW_S:.1f} s")
        fails = [p for p in pts if not p["holds"]]
        inside = [p for p in fails if p["load_nm_abs"] <= rated_torque(p["rpm"]) + 1e-9]
        zero = [p for p in inside if p["zero_fs"]]
        print(f"{inv}: {n_hold} of {len(pts)} points hold, {len(fails)} fail "
              f"({len(inside)} of them inside the rated envelope, {len(zero)} of those within "
              f"{ZERO_FS_HZ:.0f} Hz of zero stator frequency)")
        n_inside_fail += len(inside)
        for p in fails:
            print(f"  fails: {p['rpm']:+.0f} rpm {p['mode']} {p['load_nm']:+.2f} N m: {p['cause']}")
        write_results(pts, os.path.join(a.out, inv))
    date = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d")
    png = os.path.join(a.out, "capability.png")
    draw_map(sets, png, a.tol_rpm, date)
    if a.docs_png:
        shutil.copyfile(png, a.docs_png)
    wall = time.monotonic() - t_start
    print(f"\nmap: {png}" + (f" (copied to {a.docs_png})" if a.docs_png else ""))
    print(f"results: " + ", ".join(os.path.join(a.out, inv, "results.csv") for inv in inverters))
    print(f"wall time: {wall:.1f} s for {len(done)} runs on {a.jobs} workers "
          f"({cpu:.1f} s of run time summed over the runs)")
    return 1 if a.strict and n_inside_fail else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
