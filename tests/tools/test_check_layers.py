#!/usr/bin/env python3
"""tools/check_layers.py must fail, naming the file, on every kind of breach it
checks: a forbidden include (on a copy of the repository's firmware/ with one
line added), and a forbidden use, a cycle and a reach out of a reach_only file
(on copies of the host build's libraries with one object replaced by a small
one compiled here). Each copy first passes unchanged, so a failure comes from
the breach alone.

usage: test_check_layers.py   (environment: DTC_SOURCE_DIR, DTC_GENERATED_DIR,
       DTC_LIB_CONTROL, DTC_LIB_CANOPEN, DTC_LIB_DRIVE, DTC_LIB_HAL, CC, AR, NM)
"""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ENV = os.environ
ROOT = ENV.get("DTC_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))
CHECK = os.path.join(ROOT, "tools", "check_layers.py")
LIBS = {layer: ENV.get(f"DTC_LIB_{layer.upper()}") for layer in ("control", "canopen", "drive", "hal")}
GENERATED = ENV.get("DTC_GENERATED_DIR")
CC, AR, NM = ENV.get("CC", "cc"), ENV.get("AR", "ar"), ENV.get("NM", "nm")


def run_check(*args):
    p = subprocess.run([sys.executable, CHECK, "--nm", NM, *args], capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


class Includes(unittest.TestCase):
    """A copy of firmware/, hal/ and the rules; one line added per case."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="check_layers_inc_")
        for d in ("firmware", "hal"):
            shutil.copytree(os.path.join(ROOT, d), os.path.join(self.tmp, d),
                            ignore=shutil.ignore_patterns("build", "__pycache__"))
        os.makedirs(os.path.join(self.tmp, "tools"))
        shutil.copy(os.path.join(ROOT, "tools", "layers.toml"), os.path.join(self.tmp, "tools"))

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def check(self):
        args = ["--root", self.tmp]
        if GENERATED:
            args += ["--generated", GENERATED]
        return run_check(*args)

    def add_line(self, rel, line):
        path = os.path.join(self.tmp, rel)
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(text + "\n" + line + "\n")
        return text.count("\n") + 2  # the added line's number

    def assert_refused(self, rel, line, *words):
        n = self.add_line(rel, line)
        rc, out = self.check()
        self.assertEqual(rc, 1, out)
        self.assertIn(f"{rel}:{n}:", out)
        for w in words:
            self.assertIn(w, out)

    def test_the_copy_passes(self):
        rc, out = self.check()
        self.assertEqual(rc, 0, out)

    def test_control_including_a_drive_header(self):
        self.assert_refused("firmware/control/src/ctl.c", '#include "dtc/drive.h"', "dtc/drive.h", ", drive)")

    def test_control_including_a_canopen_header(self):
        self.assert_refused("firmware/control/include/dtc/observer.h", '#include "dtc/canopen/co_od.h"',
                            "firmware/canopen/include/dtc/canopen/co_od.h")

    def test_control_including_the_hal_functions(self):
        self.assert_refused("firmware/control/src/observer.c", '#include "hal/hal.h"', "hal/include/hal/hal.h",
                            "control may include only control, hal_types")

    def test_canopen_including_the_hal_functions(self):
        self.assert_refused("firmware/canopen/include/dtc/canopen/co_dev.h", '#include <hal/hal.h>', ", hal)")

    def test_canopen_including_a_drive_header(self):
        self.assert_refused("firmware/canopen/src/co_sdo.c", '#include "dtc/drive_co.h"', "dtc/drive_co.h")

    def test_drive_including_a_board_header(self):
        self.assert_refused("firmware/drive/src/drive_app.c", '#include "hal_host/hal_host.h"',
                            "hal/host/include/hal_host/hal_host.h", "board")

    def test_an_mcu_header(self):
        self.assert_refused("firmware/drive/src/drive_isr.c", "#include <stm32g4xx.h>", "not a standard C header")

    def test_an_include_that_resolves_nowhere(self):
        self.assert_refused("firmware/canopen/src/co_nmt.c", '#include "co_nmt_private.h"', "in no include folder")

    def test_rules_naming_an_unknown_layer_are_refused(self):
        rules = os.path.join(self.tmp, "tools", "layers.toml")
        with open(rules, encoding="utf-8") as fh:
            text = fh.read()
        with open(rules, "w", encoding="utf-8") as fh:
            fh.write(text.replace('may_use = ["canopen"]', 'may_use = ["canopen", "drvie"]'))
        rc, out = self.check()
        self.assertEqual(rc, 2, out)
        self.assertIn("layers.canopen.may_use names drvie", out)

    def test_a_commented_include_is_no_include(self):
        self.add_line("firmware/control/src/ctl.c", '/* #include "dtc/drive.h" */ // #include "hal/hal.h"')
        rc, out = self.check()
        self.assertEqual(rc, 0, out)


@unittest.skipUnless(all(LIBS.values()), "the host build's libraries (DTC_LIB_*) are not given")
class Symbols(unittest.TestCase):
    """Copies of the host build's libraries; one object replaced per case."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="check_layers_sym_")
        self.libs = {}
        for layer, path in LIBS.items():
            copy = os.path.join(self.tmp, f"{layer}_{os.path.basename(path)}")
            shutil.copy(path, copy)
            self.libs[layer] = copy

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def check(self, rules=None):
        args = ["--root", ROOT, "--hal-lib", self.libs["hal"]]
        if GENERATED:
            args += ["--generated", GENERATED]
        if rules:
            args += ["--rules", rules]
        for layer in ("control", "canopen", "drive"):
            args += ["--lib", f"{layer}={self.libs[layer]}"]
        return run_check(*args)

    def replace(self, layer, member, source):
        """Replace (or add) @p member of @p layer's library with @p source compiled."""
        src = os.path.join(self.tmp, "src.c")
        with open(src, "w", encoding="utf-8") as fh:
            fh.write(source)
        obj = os.path.join(self.tmp, member)
        subprocess.run([CC, "-c", "-o", obj, src], check=True)
        subprocess.run([AR, "r", self.libs[layer], obj], check=True, capture_output=True)

    def assert_refused(self, *words, rules=None):
        rc, out = self.check(rules)
        self.assertEqual(rc, 1, out)
        for w in words:
            self.assertIn(w, out)
        return out

    def test_the_copies_pass(self):
        rc, out = self.check()
        self.assertEqual(rc, 0, out)
        self.assertIn("cycles only inside the allow-list", out)

    def test_a_cycle_between_the_store_and_the_binding(self):
        # the store calling back into the binding (which calls the store)
        self.replace("drive", "persist.c.o", """
            void drive_co_apply(void *d);
            void persist_init(void *st) { drive_co_apply(st); }
            int persist_load(void *st) { (void)st; return 0; }
            int persist_save(void *st) { (void)st; return 0; }
            unsigned persist_crc32(void) { return 0u; }
        """)
        out = self.assert_refused("a cycle of files not in the allow-list", "firmware/drive/src/persist.c (drive_co_apply)",
                                  "firmware/drive/src/drive_co.c")
        self.assertIn("firmware/drive/src/persist.c reaches firmware/drive/src/drive_co.c", out)

    def test_a_cycle_inside_control(self):
        self.replace("control", "rbfn.c.o", """
            void speed_ctl_init(void);
            void rbfn_grid_derive(void) { speed_ctl_init(); }
        """)
        self.assert_refused("a cycle of files not in the allow-list", "firmware/control/src/rbfn.c (speed_ctl_init)",
                            "firmware/control/src/speed_ctl.c")

    def test_the_interrupt_side_reaching_the_bus(self):
        self.replace("drive", "drive_isr.c.o", """
            int co_dev_send(void *c, const void *f);
            void drive_isr(void *ctx) { (void)co_dev_send(ctx, 0); }
            void drive_isr_init(void *d) { (void)d; }
        """)
        self.assert_refused("firmware/drive/src/drive_isr.c reaches firmware/canopen/src/co_dev.c",
                            "knows nothing of the CANopen binding")

    def test_the_interrupt_side_reaching_the_store(self):
        self.replace("drive", "drive_isr.c.o", """
            int persist_load(void *st);
            void drive_isr(void *ctx) { (void)persist_load(ctx); }
        """)
        self.assert_refused("firmware/drive/src/drive_isr.c reaches firmware/drive/src/persist.c")

    def test_control_using_the_drive(self):
        self.replace("control", "num_math.c.o", """
            const void *drive_cfg(const void *d);
            float num_expf(float x) { return drive_cfg(0) ? x : 0.0f; }
        """)
        self.assert_refused("firmware/control/src/num_math.c uses drive_cfg of firmware/drive/src/drive_isr.c (drive)",
                            "control may use only control")

    def test_canopen_using_a_hal_function(self):
        self.replace("canopen", "co_nmt.c.o", """
            int hal_can_send(const void *f);
            void co_nmt_init(void *n) { (void)hal_can_send(n); }
        """)
        self.assert_refused("firmware/canopen/src/co_nmt.c uses hal_can_send, a HAL function",
                            "canopen may use only canopen")

    def test_the_drive_using_the_host_binding(self):
        self.replace("drive", "drive_app.c.o", """
            void hal_host_bind(void *b);
            void drive_init(void *d) { hal_host_bind(d); }
            void drive_background(void *d) { (void)d; }
        """)
        self.assert_refused("firmware/drive/src/drive_app.c uses hal_host_bind, a function of the host binding")

    def test_an_allow_list_larger_than_its_cycle(self):
        rules = os.path.join(self.tmp, "layers.toml")
        with open(os.path.join(ROOT, "tools", "layers.toml"), encoding="utf-8") as fh:
            text = fh.read()
        anchor = '"firmware/canopen/src/co_dev.c",'
        self.assertIn(anchor, text)
        with open(rules, "w", encoding="utf-8") as fh:
            fh.write(text.replace(anchor, anchor + ' "firmware/canopen/src/co_cia402.c",'))
        self.assert_refused("allowed_cycles names firmware/canopen/src/co_cia402.c, in no cycle now", rules=rules)

    def test_an_object_without_its_source(self):
        self.replace("drive", "unity_0.c.o", "int unity_0;\n")
        rc, out = self.check()
        self.assertEqual(rc, 2, out)
        self.assertIn("unity_0.c.o", out)


if __name__ == "__main__":
    unittest.main(verbosity=2)
