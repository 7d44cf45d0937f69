#!/usr/bin/env python3
"""Negative tests of tools/svd/check_regs.py: a temporary copy of a register
header with one deliberate mistake must make the checker fail and name the
define. Exit 0 when every mutation is caught.

    test_svd_negative.py           the firmware's header, hal/stm32g4/stm32g474_regs.h
    test_svd_negative.py models    the twin's models' header, host_sim/board/src/g474_regs.h
"""
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CHECKER = os.path.join(ROOT, "tools/svd/check_regs.py")
HEADERS = {
    "firmware": (os.path.join(ROOT, "hal/stm32g4/stm32g474_regs.h"),
                 os.path.join(ROOT, "hal/stm32g4/svd/stm32g474_subset.json")),
    "models": (os.path.join(ROOT, "host_sim/board/src/g474_regs.h"),
               os.path.join(ROOT, "host_sim/board/svd/stm32g474_models_subset.json")),
}

# (description, text in the header, replacement, name the checker must report)
MUTATIONS = {"firmware": [
    ("wrong register address", "#define RCC_CR REG32(RCC_BASE + 0x00u)",
     "#define RCC_CR REG32(RCC_BASE + 0x04u)", "RCC_CR"),
    ("wrong peripheral base", "#define HRTIM_TIMC_BASE 0x40016980u", "#define HRTIM_TIMC_BASE 0x40016A00u",
     "HRTIM_TIMC_BASE"),
    ("wrong bit", "#define FLASH_CR_STRT (1u << 16)", "#define FLASH_CR_STRT (1u << 17)", "FLASH_CR_STRT"),
    ("wrong shift", "#define FDCAN_NBTP_NBRP_SHIFT 16u", "#define FDCAN_NBTP_NBRP_SHIFT 17u",
     "FDCAN_NBTP_NBRP_SHIFT"),
    ("field value too wide", "#define ADC12_CCR_DUAL_INJ_SIMULT (5u << 0) /* @svd ADC12_Common.CCR.DUAL=5",
     "#define ADC12_CCR_DUAL_INJ_SIMULT (5u << 0) /* @svd ADC12_Common.CCR.DUAL=37", "ADC12_CCR_DUAL_INJ_SIMULT"),
    ("ADC3 at ADC4's base", "#define ADC3_BASE 0x50000400u", "#define ADC3_BASE 0x50000500u", "ADC3_BASE"),
    ("wrong ADC3 result register", "#define ADC3_JDR1 REG32(ADC3_BASE + 0x80u)", "#define ADC3_JDR1 REG32(ADC3_BASE + 0x84u)",
     "ADC3_JDR1"),
    ("wrong clock-enable bit", "#define RCC_AHB2ENR_ADC345EN (1u << 14)", "#define RCC_AHB2ENR_ADC345EN (1u << 15)",
     "RCC_AHB2ENR_ADC345EN"),
    ("external event 6 reset at event 7's bit", "#define HRTIM_RST_EXTEVNT6 (1u << 26)",
     "#define HRTIM_RST_EXTEVNT6 (1u << 27)", "HRTIM_RST_EXTEVNT6"),
    ("wrong external-event register", "#define HRTIM_EECR3 REG32(HRTIM_COMMON_BASE + 0x38u)",
     "#define HRTIM_EECR3 REG32(HRTIM_COMMON_BASE + 0x34u)", "HRTIM_EECR3"),
    ("untagged define", "#define HRTIM_MREP REG32(HRTIM_MASTER_BASE + 0x18u)  /* @svd HRTIM_Master.MREP */",
     "#define HRTIM_MREP REG32(HRTIM_MASTER_BASE + 0x18u)", "HRTIM_MREP"),
], "models": [
    ("wrong register offset", "#define HRTIM_DTxR_OFS 0x38u", "#define HRTIM_DTxR_OFS 0x3Cu", "HRTIM_DTxR_OFS"),
    ("wrong field mask", "#define HRTIM_DTxR_DTPRSC (7u << 10)", "#define HRTIM_DTxR_DTPRSC (7u << 11)",
     "HRTIM_DTxR_DTPRSC"),
    ("a field one bit too narrow", "#define HRTIM_DTxR_DTFx (0x1FFu << 16)", "#define HRTIM_DTxR_DTFx (0xFFu << 16)",
     "HRTIM_DTxR_DTFx"),
    ("the master's update flag at the sync flag's bit", "#define HRTIM_MISR_MUPD (1u << 6)",
     "#define HRTIM_MISR_MUPD (1u << 5)", "HRTIM_MISR_MUPD"),
    ("wrong peripheral base", "#define HRTIM_COMMON_BASE 0x40016B80u", "#define HRTIM_COMMON_BASE 0x40016B00u",
     "HRTIM_COMMON_BASE"),
    ("field value of the wrong field code", "#define HRTIM_OUTxR_FAULT1_ACTIVE (1u << 4)",
     "#define HRTIM_OUTxR_FAULT1_ACTIVE (2u << 4)", "HRTIM_OUTxR_FAULT1_ACTIVE"),
    ("untagged define", "#define HRTIM_SIZE 0x800u                      /* @const",
     "#define HRTIM_SIZE 0x800u                      /* ", "HRTIM_SIZE"),
]}


def run(header, subset):
    return subprocess.run([sys.executable, CHECKER, "--header", header, "--subset", subset], capture_output=True,
                          text=True)


def main():
    which = sys.argv[1] if len(sys.argv) > 1 else "firmware"
    if which not in HEADERS:
        print("usage: test_svd_negative.py [firmware|models]")
        return 2
    header, subset = HEADERS[which]
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        copy = os.path.join(tmp, os.path.basename(header))
        shutil.copy(header, copy)
        base = run(copy, subset)
        if base.returncode != 0:
            print("unmodified copy fails:\n" + base.stderr)
            return 1
        with open(header, encoding="utf-8") as f:
            original = f.read()
        for desc, old, new, name in MUTATIONS[which]:
            if original.count(old) != 1:
                print("FAIL %s: text not found once in the header: %r" % (desc, old))
                failures += 1
                continue
            with open(copy, "w", encoding="utf-8") as f:
                f.write(original.replace(old, new))
            r = run(copy, subset)
            if r.returncode == 0 or name not in r.stderr:
                print("FAIL %s: checker exit %d\n%s" % (desc, r.returncode, r.stderr))
                failures += 1
            else:
                print("ok   %s: %s" % (desc, r.stderr.splitlines()[0]))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
