#!/usr/bin/env python3
"""Negative tests of tools/svd/check_regs.py: a temporary copy of the register
header with one deliberate mistake must make the checker fail and name the
define. Exit 0 when every mutation is caught."""
import os
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
HEADER = os.path.join(ROOT, "hal/stm32g4/stm32g474_regs.h")
CHECKER = os.path.join(ROOT, "tools/svd/check_regs.py")

# (description, text in the header, replacement, name the checker must report)
MUTATIONS = [
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
]


def run(header):
    return subprocess.run([sys.executable, CHECKER, "--header", header], capture_output=True, text=True)


def main():
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        copy = os.path.join(tmp, "stm32g474_regs.h")
        shutil.copy(HEADER, copy)
        base = run(copy)
        if base.returncode != 0:
            print("unmodified copy fails:\n" + base.stderr)
            return 1
        with open(HEADER, encoding="utf-8") as f:
            original = f.read()
        for desc, old, new, name in MUTATIONS:
            if original.count(old) != 1:
                print("FAIL %s: text not found once in the header: %r" % (desc, old))
                failures += 1
                continue
            with open(copy, "w", encoding="utf-8") as f:
                f.write(original.replace(old, new))
            r = run(copy)
            if r.returncode == 0 or name not in r.stderr:
                print("FAIL %s: checker exit %d\n%s" % (desc, r.returncode, r.stderr))
                failures += 1
            else:
                print("ok   %s: %s" % (desc, r.stderr.splitlines()[0]))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
