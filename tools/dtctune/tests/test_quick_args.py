"""quick_args (the short commands read without argparse) against argparse (parser.py), the one
definition of dtctune's grammar: whatever the quick path accepts, argparse must read the same."""
import random

import pytest

from dtctune import quick_args
from dtctune.errors import DtctuneError
from dtctune.parser import build_parser

# Everything a line may contain: options of both levels, their abbreviations and `=` forms,
# values (good, bad, negative, empty) and the command words.
TOKENS = ["--interface", "socketcan", "virtual", "--channel", "vcan0", "can1", "--bitrate", "500000",
          "x1", "--node", "1", "5", "0x7f", "0", "128", "abc", "--eds", "drive.eds", "--timeout", "0.2",
          "-1", "nan", "inf", "--chan", "--node=3", "--", "-h", "--help", "--version",
          "get", "set", "save", "restore-defaults", "list", "monitor", "record", "scope", "gett",
          "rbfn_gamma_w", "speed_ref_rpm", "0x2001:3", "", "-5", "4000",
          "--value-only", "--value", "--no-check", "--all", "--no-values", "--long", "--filter", "rbfn",
          "--start", "--seconds"]


def argparse_reads(argv):
    """vars() of argparse's reading, or None when it refuses the line."""
    try:
        return vars(build_parser().parse_args(argv))
    except (DtctuneError, SystemExit):
        return None


@pytest.mark.parametrize("argv", [
    ["get", "rbfn_gamma_w"], ["get", "a", "b", "--value-only"], ["--value-only"][:0] + ["get", "--value-only", "a"],
    ["set", "rbfn_gamma_w", "5000"], ["set", "--no-check", "rbfn_k", "2000"], ["save"], ["restore-defaults"],
    ["list", "--filter", "rbfn"], ["list", "--all", "--no-values", "--long"],
    ["--channel", "can1", "--node", "0x7f", "--timeout", "0.5", "--eds", "x.eds", "get", "0x2001:3"],
    ["--interface", "virtual", "--bitrate", "250000", "set", "speed_ref_rpm", "600"],
])
def test_the_readme_forms_take_the_quick_path_and_read_as_argparse_does(argv):
    quick = quick_args.parse(argv)
    assert quick is not None, argv
    assert vars(quick) == argparse_reads(argv)


@pytest.mark.parametrize("argv", [[], ["--help"], ["get"], ["set", "a"], ["set", "a", "1", "2"], ["get", "-5"],
                                  ["--node", "0", "get", "a"], ["--node", "x", "get", "a"], ["--timeout", "-1", "save"],
                                  ["--chan", "vcan0", "save"], ["--node=3", "save"], ["save", "--node", "2"],
                                  ["get", "a", "--value-only", "b"], ["monitor"], ["list", "--filter"],
                                  ["list", "--filter", "-x"], ["--", "get", "a"], ["gett", "a"]])
def test_what_the_quick_path_leaves_to_argparse(argv):
    assert quick_args.parse(argv) is None


def test_random_lines_the_quick_path_accepts_read_the_same_in_argparse():
    rng = random.Random(12)
    accepted = 0
    for _ in range(20000):
        argv = [rng.choice(TOKENS) for _ in range(rng.randint(0, 7))]
        if rng.random() < 0.5:  # most random lines have no command in the right place: make some
            argv.insert(rng.randint(0, len(argv)), rng.choice(list(quick_args.COMMANDS)))
        quick = quick_args.parse(argv)
        if quick is not None:
            accepted += 1
            assert vars(quick) == argparse_reads(argv), argv
    assert accepted > 800  # the comparison did happen on many lines


def test_converters_word_their_refusal():
    assert quick_args.node_id("0x10") == 16
    for bad in ("0", "128", "x"):
        with pytest.raises(quick_args.ArgError, match="node id"):
            quick_args.node_id(bad)
    assert quick_args.positive("0.25") == 0.25
    for bad in ("0", "-1", "nan", "inf", "x"):
        with pytest.raises(quick_args.ArgError):
            quick_args.positive(bad)
