"""README as a test, outside its CAN walk-through (can.uml_readme runs that one): every command
line of every ```sh block in README.md runs as printed, from a scratch directory that looks like
the repository (links to build, host_sim, tools, docs), and must exit 0 and write what it says.

What a line may be, and how it is checked:
  * `tools/run-paper-case.sh`, `tools/run-all-tests.sh`: the two commands. The second is this
    suite (CI runs it; here it would recurse), the first installs and builds like it and then
    runs dtc-sim as the lines below do. Here: each exists and is executable.
  * `cmake --preset P && cmake --build --preset P`: the exact configure-and-build lines that
    tools/run-all-tests.sh runs before the tests (re-running them under a parallel ctest would
    reconfigure the tree the other tests use), so they are checked to be those lines.
  * `cmake --build --preset stm32g4 --target flash`: needs a probe; checked to be a target of
    the stm32g4 build (its build.ninja has it).
  * any other line (dtc-sim, dtc-board): run with `sh -c`, exit status 0, and every file it
    names after --csv/--metrics/--png written and not empty.
Lines inside the "Tuning over CAN" section are left to can.uml_readme.

Environment: DTC_BUILD_DIR (the host build, for the dtc-sim/dtc-board paths the README prints
relative to the repository).
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
README = ROOT / "README.md"


def blocks():
    """[(section title, [command lines])] of every ```sh block outside 'Tuning over CAN'."""
    text = README.read_text(encoding="utf-8")
    out = []
    for sec in re.finditer(r"^## (.+?)\n(.*?)(?=^## |\Z)", text, re.S | re.M):
        title, body = sec.group(1), sec.group(2)
        if title.startswith("Tuning over CAN"):
            continue
        for b in re.finditer(r"^```sh\n(.*?)^```", body, re.S | re.M):
            lines = []
            for line in b.group(1).splitlines():
                cmd = re.sub(r"\s+#.*$", "", line).strip()
                if cmd and not cmd.startswith("#"):
                    lines.append(cmd)
            out.append((title, lines))
    return out


INLINE_FLASH = "cmake --build --preset stm32g4 --target flash"


class ReadmeCommands(unittest.TestCase):
    def test_found(self):
        """The extraction itself: the blocks a newcomer needs are there."""
        words = " ".join(" ".join(ls) for _, ls in blocks())
        for needed in ("tools/run-paper-case.sh", "tools/run-all-tests.sh", "dtc-sim run", "dtc-board run"):
            self.assertIn(needed, words, "README lost its '%s' line" % needed)
        self.assertIn("`%s`" % INLINE_FLASH, README.read_text(encoding="utf-8"))

    def test_every_line_runs(self):
        script = (ROOT / "tools" / "run-all-tests.sh").read_text()
        build_dir = Path(os.environ.get("DTC_BUILD_DIR", ROOT / "build" / "host"))
        work = Path(tempfile.mkdtemp(prefix="dtc-readme-cmds-"))
        for name in ("host_sim", "tools", "docs"):
            os.symlink(ROOT / name, work / name)
        (work / "build").mkdir()
        os.symlink(build_dir, work / "build" / "host")
        os.symlink(build_dir.parent / "stm32g4", work / "build" / "stm32g4")
        ran = 0
        for title, lines in blocks():
            for cmd in lines:
                with self.subTest(section=title, command=cmd):
                    if cmd in ("tools/run-paper-case.sh", "tools/run-all-tests.sh"):
                        self.assertTrue(os.access(ROOT / cmd, os.X_OK), cmd)
                        continue
                    if cmd.startswith("cmake "):
                        for part in cmd.split("&&"):
                            part = part.strip()
                            flags = part.replace("cmake --preset", "").strip()
                            self.assertTrue(part + " " in script or part + "\n" in script
                                            or (part.startswith("cmake --preset ") and
                                                ("cmake --preset %s " % flags) in script),
                                            "%r is not what tools/run-all-tests.sh runs" % part)
                        continue
                    r = subprocess.run(["sh", "-c", cmd], cwd=work, capture_output=True, text=True, timeout=600)
                    self.assertEqual(r.returncode, 0, "%s\n%s%s" % (cmd, r.stdout, r.stderr))
                    argv = shlex.split(cmd)
                    for flag in ("--csv", "--metrics", "--png"):
                        if flag in argv:
                            f = work / argv[argv.index(flag) + 1]
                            self.assertTrue(f.is_file() and f.stat().st_size > 0, "%s did not write %s" % (cmd, f))
                    ran += 1
        self.assertGreaterEqual(ran, 2)
        ninja = (build_dir.parent / "stm32g4" / "build.ninja")
        if ninja.exists():
            self.assertIn("build flash:", ninja.read_text(), "the stm32g4 build has no 'flash' target")


if __name__ == "__main__":
    unittest.main(verbosity=2)
