#!/usr/bin/env python3
"""The emulated board ("twin") against dtc-sim and closed-form values.

  test_twin.py case2 CONTROLLER   CASE2 on the twin and on dtc-sim with the same controller:
                                  recovery time within 10 %, steady and estimate errors within
                                  0.5 rpm of dtc-sim's; no switching violation; every dead time
                                  1 us +- one HRTIM tick (1/170 MHz); the control tick ran; the
                                  three phase currents sampled at one instant (within one ADC
                                  clock, 1 / 42.5 MHz) in every PWM period, at the end of the
                                  24.5-cycle sampling window after the HRTIM trigger.
  test_twin.py fault              the gate drivers' fault line (PB10 = FLT3 and PB5 = EEV6) pulled
                                  low mid-run: outer switches (S1, S4) off within 60 ns
                                  (docs/board.md: 20-60 ns), the inner ones (S2, S3) after them, in
                                  the window the EEV6 digital filter gives (8 samples at 170 MHz /
                                  16, then 3 tHRTIM: 0.677-0.771 us after the line), so all within
                                  1 us; the core reports CTL_FAULT_HW, the board BOARD_FAULT_HRTIM,
                                  and a node on the CAN bus receives the EMCY 0x2320 (CiA 301
                                  "current, device output side"; the parameter table's code for
                                  CTL_FAULT_HW) with the current bit of the error register and
                                  CTL_FAULT_HW in the fault word, after the line fell and within
                                  10 ms. Then the same with the HRTIM1_FLT interrupt's NVIC enable
                                  cleared just before the line falls (dtc-board --fault-irq-off):
                                  the interrupt never runs and the inner switches go off at the
                                  same instant: the sequence is hardware.
Exit 77 (skipped) when the flashable image has not been built (cmake --preset stm32g4).
"""
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tools"))
from scenario_as_flashed import as_flashed  # noqa: E402

SRC = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get("DTC_HOST_BIN", os.path.join(SRC, "build", "host", "bin"))
ELF = os.environ.get("DTC_FW_ELF", os.path.join(SRC, "build", "stm32g4", "dtc-fw.elf"))
CASE2 = os.path.join(SRC, "host_sim", "scenarios", "case2.ini")
T_HRTIM = 1.0 / 170e6
DEAD_TIME = 1.0e-6            # BOARD_DEAD_TIME_NS (hal/stm32g4/board.h)
T_EEV_SAMPLE = 16 * T_HRTIM  # EEV6 filter EE6F = 1100: fSAMPLING = fEEVS / 16, fEEVS = fHRTIM (EEVSD = 0)
EEV_N = 8                     # ... N = 8 consecutive samples (RM0440, HRTIM_EECR3)
EEV_SYNC = 3 * T_HRTIM        # resynchronisation before acting on the outputs (as FLT3)
INNER_MIN = (EEV_N - 1) * T_EEV_SAMPLE + EEV_SYNC  # the line falls just after a sample
INNER_MAX = EEV_N * T_EEV_SAMPLE + EEV_SYNC        # ... or just on one
ALL_OFF_WITHIN = 1.0e-6       # the requirement: every output inactive within a microsecond of a fault
EMCY_HW = 0x2320              # tools/params/parameters.toml [[emcy]] CTL_FAULT_HW
ERR_REG_CURRENT = 1 << 1      # CiA 301 0x1001 bit 1
MIN_PULSE = 2.0e-6            # BOARD_MIN_PULSE_NS: shortest second-vector pulse (npc_plan.c)
T_ADC = 4.0 / 170e6           # ADC clock HCLK / 4 (ADC12_CCR, ADC345_CCR CKMODE = 3)
SAMPLING_WINDOW = 24.5 * T_ADC  # SMP = 24.5 ADC cycles: the sample is taken at the window's end
CTL_FAULT_HW = 1 << 6
BOARD_FAULT_HRTIM = 1 << 5
BOARD_FAULT_LINE_PINS = 1 << 12  # hal/stm32g4/board.h: PB5 and PB10 read differently
PERIOD_S = 200e-6

failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def run(args):
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stdout + r.stderr)
        sys.exit(f"{args[0]} exited with {r.returncode}")
    return r.stdout


def metrics(tmp, name, args):
    path = os.path.join(tmp, name + ".json")
    out = run(args + ["--metrics", path])
    print(out.strip())
    with open(path) as f:
        return json.load(f)


def case2_as_flashed(tmp):
    """case2.ini as the flashed image runs it (tools/scenario_as_flashed.py): both runs use the
    firmware's defaults, the plant the 1 V device drop they compensate."""
    return as_flashed(CASE2, os.path.join(tmp, "case2_as_flashed.ini"))


def common_board_checks(b):
    v = b["violations"]
    check(v["total"] == 0, f"switching violations: {v}")
    check(b["dead_time_events"] > 1000, f"dead times seen: {b['dead_time_events']}")
    check(abs(b["min_dead_time_s"] - DEAD_TIME) <= T_HRTIM + 1e-12 and
          abs(b["max_dead_time_s"] - DEAD_TIME) <= T_HRTIM + 1e-12,
          f"dead time {b['min_dead_time_s'] * 1e9:.2f}..{b['max_dead_time_s'] * 1e9:.2f} ns = 1000 ns +- 5.9 ns")
    shortest = min(min(s["min_on_s"], s["min_off_s"]) for s in b["switches"].values())
    check(shortest >= MIN_PULSE - DEAD_TIME - T_HRTIM,
          f"shortest gate pulse {shortest * 1e6:.3f} us >= minimum vector pulse - dead time (1 us)")
    cs = b["current_sampling"]
    check(cs["triggers"] > 1000, f"ia, ib, ic converted together on {cs['triggers']} triggers")
    check(cs["max_skew_s"] <= T_ADC,
          f"ia/ib/ic sampling instants at most {cs['max_skew_s'] * 1e9:.2f} ns apart (<= one ADC clock, 23.5 ns)")
    for k in ("ia", "ib", "ic"):
        t = cs[k + "_after_trigger_s"]
        check(abs(t - SAMPLING_WINDOW) <= T_ADC, f"{k} sampled {t * 1e9:.1f} ns after the trigger (24.5 ADC cycles = 576 ns)")
    tick = b["interrupt_instructions"].get("ADC1_2 (control tick)")
    check(tick is not None and tick["count"] > 1000 and tick["worst"] >= tick["mean"] > 0,
          f"control tick instructions: {tick}")


def case2(controller):
    with tempfile.TemporaryDirectory() as tmp:
        case2 = case2_as_flashed(tmp)
        sim = metrics(tmp, "sim", [os.path.join(BIN, "dtc-sim"), "run", case2, "--controller", controller, "--quiet"])
        twin = metrics(tmp, "twin", [os.path.join(BIN, "dtc-board"), "run", case2, "--elf", ELF,
                                     "--controller", controller])
    rs, rt = sim["recovery_time_s"], twin["recovery_time_s"]
    check(rs > 0 and abs(rt - rs) <= 0.10 * rs, f"recovery {rt:.4f} s vs dtc-sim {rs:.4f} s (10 %)")
    for k in ("steady_error_rpm", "speed_est_error_rpm"):
        check(abs(twin[k] - sim[k]) <= 0.5, f"{k} {twin[k]:.3f} vs dtc-sim {sim[k]:.3f} (0.5 rpm)")
    check(twin["controller"] == controller, f"controller {twin['controller']}")
    check(twin["faults"] == 0, f"no telemetry fault ({twin['faults']:#x})")
    common_board_checks(twin["board"])


def fault_run(tmp, name, extra):
    twin = metrics(tmp, name, [os.path.join(BIN, "dtc-board"), "run", case2_as_flashed(tmp), "--elf", ELF,
                               "--set", "sim.duration_s=1.0", "--set", "metrics.window=before 0.5 0.6",
                               "--fault-line", "0.8"] + extra)
    f = twin["board"]["fault"]
    print(json.dumps(f))
    check(f["outer_on_at_fault"] >= 1 and f["inner_on_at_fault"] >= 1, "switches were on when the line fell")
    check(0 < f["outer_off_after_s"] <= 60e-9, f"outer switches off after {f['outer_off_after_s'] * 1e9:.1f} ns (<= 60 ns)")
    check(f["outer_off_after_s"] < f["inner_off_after_s"],
          f"outer switches off before the inner ones ({f['outer_off_after_s'] * 1e9:.1f} ns < "
          f"{f['inner_off_after_s'] * 1e9:.1f} ns)")
    check(INNER_MIN - 1e-12 <= f["inner_off_after_s"] <= INNER_MAX + 1e-12,
          f"inner switches off {f['inner_off_after_s'] * 1e6:.3f} us after the line (EEV6 filter: "
          f"{INNER_MIN * 1e6:.3f}..{INNER_MAX * 1e6:.3f} us)")
    check(f["inner_off_after_s"] < ALL_OFF_WITHIN,
          f"inner switches off within 1 us of the line ({f['inner_off_after_s'] * 1e6:.3f} us)")
    check(f["telemetry_faults_after"] & CTL_FAULT_HW, f"the core reports CTL_FAULT_HW ({f['telemetry_faults_after']:#x})")
    check(twin["board"]["violations"]["total"] == 0, "no switching violation through the trip")
    return twin, f


def fault():
    with tempfile.TemporaryDirectory() as tmp:
        twin, f = fault_run(tmp, "twin", [])
        flt = twin["board"]["interrupt_instructions"].get("HRTIM1_FLT")
        check(flt is not None and flt["count"] == 1, f"one fault interrupt (the software back-up): {flt}")
        check(f["board_faults"] & BOARD_FAULT_HRTIM, f"the board records BOARD_FAULT_HRTIM ({f['board_faults']:#x})")
        emcy = [e for e in twin["board"]["can"]["emcy"] if e["code"] == EMCY_HW]
        print(json.dumps(twin["board"]["can"]))
        t_line = f["line_low_at_s"]
        check(len(emcy) == 1, f"one EMCY {EMCY_HW:#06x} on the bus ({len(emcy)})")
        if emcy:
            e = emcy[0]
            check(t_line < e["t_s"] <= t_line + 10e-3, f"EMCY {(e['t_s'] - t_line) * 1e3:.2f} ms after the line fell (<= 10 ms)")
            check(e["error_register"] & ERR_REG_CURRENT and e["faults"] & CTL_FAULT_HW,
                  f"EMCY error register {e['error_register']:#x} (current bit), fault word {e['faults']:#x} (CTL_FAULT_HW)")
            check(e["cob_id"] & 0x780 == 0x080, f"EMCY COB-ID {e['cob_id']:#x} = 0x80 + node id")
        print("-- again with the HRTIM1_FLT interrupt disabled in the NVIC: hardware only")
        twin2, f2 = fault_run(tmp, "twin_irq_off", ["--fault-irq-off"])
        flt2 = twin2["board"]["interrupt_instructions"].get("HRTIM1_FLT")
        check(flt2 is None, f"the fault interrupt never ran: {flt2}")
        check(not f2["board_faults"] & BOARD_FAULT_HRTIM,
              f"so the board did not record BOARD_FAULT_HRTIM ({f2['board_faults']:#x})")
        check(abs(f2["inner_off_after_s"] - f["inner_off_after_s"]) <= 1e-12 and
              abs(f2["outer_off_after_s"] - f["outer_off_after_s"]) <= 1e-12,
              "outer and inner turn-off instants identical with and without the interrupt")


def fault_eev6_only():
    """PB5 (EEV6) low while PB10 (FLT3) stays high: a broken link between the two pins of the one
    fault line, or a stuck PB5. EEV6 holds every inner switch off (hardware) and the outer ones come
    on as their complements (S1 + S4: no shoot-through, the leg floats on its diodes); the next tick
    reads PB5 as a fault line, the core stops on CTL_FAULT_HW and the software turns every output
    off; the board records the pin mismatch and refuses to enable the gates while PB5 is low."""
    with tempfile.TemporaryDirectory() as tmp:
        twin = metrics(tmp, "twin_eev6", [os.path.join(BIN, "dtc-board"), "run", case2_as_flashed(tmp), "--elf", ELF,
                                          "--set", "sim.duration_s=1.0", "--set", "metrics.window=before 0.5 0.6",
                                          "--fault-line", "0.8", "--fault-pins", "eev6"])
        f = twin["board"]["fault"]
        print(json.dumps(f))
        check(f["inner_on_at_fault"] >= 1 and f["outer_on_at_fault"] >= 1, "switches were on when PB5 fell")
        check(0 < f["inner_off_after_s"] < ALL_OFF_WITHIN,
              f"inner switches off {f['inner_off_after_s'] * 1e6:.3f} us after PB5 (hardware, EEV6)")
        check(0 < f["outer_off_after_s"] <= 2 * PERIOD_S + ALL_OFF_WITHIN,
              f"outer switches off {f['outer_off_after_s'] * 1e6:.1f} us after PB5 (the core's fault reaction, "
              f"within two control periods)")
        check(f["telemetry_faults_after"] & CTL_FAULT_HW, f"the core reports CTL_FAULT_HW ({f['telemetry_faults_after']:#x})")
        check(f["board_faults"] & BOARD_FAULT_LINE_PINS,
              f"the board records the PB5/PB10 mismatch ({f['board_faults']:#x})")
        check(not f["board_faults"] & BOARD_FAULT_HRTIM, f"FLT3 never tripped ({f['board_faults']:#x})")
        v = twin["board"]["violations"]
        # Until the software turns them off the outer switches are on with the inner ones off
        # (S1 + S4: counted as bad combinations, no path across the link); never an overlap of a
        # complementary pair (S1 + S3, S2 + S4) and never a P<->N step.
        check(v["pair_overlap"] == 0 and v["pn_step"] == 0,
              f"no pair overlap, no P<->N step (bad combinations until the turn-off: {v['bad_combination']})")
        check(twin["speed_true_end_rpm"] < 480.0 and twin["faults"] & CTL_FAULT_HW,
              f"the drive stayed stopped: {twin['speed_true_end_rpm']:.1f} rpm at the end, faults {twin['faults']:#x}")


def fault_restart():
    """The gate re-enable after a trip, end to end: the line falls at 0.8 s, rises at 1.0 s, the
    faults are cleared 2 ms later (as a CAN fault reset does) and the drive restarts CASE2 from
    where the motor coasted: no switching violation at the trip or at the re-enable (the latches
    EEV6 reset are set to O before the outputs come back, hal_gate_enable), the fault gone, the
    speed back near 500 rpm."""
    with tempfile.TemporaryDirectory() as tmp:
        twin = metrics(tmp, "twin_restart", [os.path.join(BIN, "dtc-board"), "run", case2_as_flashed(tmp),
                                             "--elf", ELF, "--set", "sim.duration_s=2.5",
                                             "--set", "metrics.window=after 2.3 2.5",
                                             "--fault-line", "0.8", "--fault-release", "1.0"])
        f = twin["board"]["fault"]
        print(json.dumps(f), json.dumps(twin["board"]["violations"]))
        check(f["telemetry_faults_after"] & CTL_FAULT_HW, f"the trip was seen ({f['telemetry_faults_after']:#x})")
        check(twin["board"]["violations"]["total"] == 0, "no switching violation through trip and re-enable")
        check(twin["faults"] == 0, f"no fault left at the end ({twin['faults']:#x})")
        check(abs(twin["window_after_speed_rpm"] - 500.0) <= 20.0,
              f"the drive restarted: {twin['window_after_speed_rpm']:.1f} rpm over 2.3-2.5 s")


def main():
    if not os.path.exists(ELF):
        print(f"skipped: {ELF} not built (cmake --preset stm32g4 && cmake --build --preset stm32g4)")
        return 77
    if sys.argv[1] == "case2":
        case2(sys.argv[2])
    elif sys.argv[1] == "fault":
        fault()
    elif sys.argv[1] == "fault_eev6":
        fault_eev6_only()
    elif sys.argv[1] == "fault_restart":
        fault_restart()
    else:
        sys.exit("usage: test_twin.py case2 rbfn|ip | fault")
    if failures:
        print(f"{len(failures)} check(s) failed")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
