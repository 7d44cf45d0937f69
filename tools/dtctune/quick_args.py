"""The quick path of dtctune's command line: the short commands (get, set, save,
restore-defaults, list) in their plain forms, read without argparse.

Each of those commands is a new process, and inside User-Mode Linux importing argparse (with re,
gettext and locale) takes about 0.1 s of its start-up (tools/dtctune_bench.py startup). parse()
takes the forms it knows and returns None for everything else: --help, --version, abbreviated or
`--opt=value` options, `--`, values that start with '-', the long-running commands, and every
mistake. argparse (parser.py) then reads the line as before, so it alone defines the grammar and
words every usage error; a test checks that whatever this module accepts, argparse reads the same.
"""
from __future__ import annotations

from types import SimpleNamespace


class ArgError(ValueError):
    """A value a converter refuses (argparse turns it into a usage error)."""


def node_id(text: str) -> int:
    """A CANopen node id, 1..127, in any int() notation."""
    try:
        v = int(text, 0)
    except ValueError:
        raise ArgError("node id must be a number 1..127, got '%s'" % text) from None
    if not 1 <= v <= 127:
        raise ArgError("node id must be 1..127, got %d" % v)
    return v


def positive(text: str) -> float:
    """A finite number > 0."""
    try:
        v = float(text)
    except ValueError:
        raise ArgError("'%s' is not a number" % text) from None
    if not v > 0 or v != v or v == float("inf"):
        raise ArgError("must be a positive number, got '%s'" % text)
    return v


# Options before the command: name -> (attribute, converter, default). Must match parser.py.
GLOBAL_OPTIONS = {
    "--interface": ("interface", str, "socketcan"),
    "--channel": ("channel", str, "vcan0"),
    "--bitrate": ("bitrate", int, None),
    "--node": ("node", node_id, 1),
    "--eds": ("eds", str, None),
    "--timeout": ("timeout", positive, 1.0),
}

# command -> (positional attributes with their count (+ = one or more), flags, valued options).
COMMANDS = {
    "get": ((("names", "+"),), {"--value-only": "value_only"}, {}),
    "set": ((("name", 1), ("value", 1)), {"--no-check": "no_check"}, {}),
    "save": ((), {}, {}),
    "restore-defaults": ((), {}, {}),
    "list": ((), {"--all": "all", "--no-values": "no_values", "--long": "long"}, {"--filter": "filter"}),
}


def _value(argv, i):
    """The value after argv[i], or None when missing or option-like."""
    if i + 1 >= len(argv) or argv[i + 1].startswith("-"):
        return None
    return argv[i + 1]


def parse(argv):
    """The parsed command line (attributes as argparse would set them), or None when argparse
    must read it."""
    ns = {attr: default for attr, _, default in GLOBAL_OPTIONS.values()}
    i = 0
    while i < len(argv) and argv[i].startswith("-"):
        opt = GLOBAL_OPTIONS.get(argv[i])
        value = _value(argv, i)
        if opt is None or value is None:
            return None
        attr, convert, _ = opt
        try:
            ns[attr] = convert(value)
        except ValueError:
            return None
        i += 2
    if i >= len(argv) or argv[i] not in COMMANDS:
        return None
    command = argv[i]
    positionals, flags, options = COMMANDS[command]
    ns["command"] = command
    for attr in flags.values():
        ns[attr] = False
    for attr in options.values():
        ns[attr] = None
    words = []
    after_word = False  # positionals split by flags: argparse may read those differently
    i += 1
    while i < len(argv):
        a = argv[i]
        if a in flags:
            ns[flags[a]] = True
            after_word = False
        elif a in options:
            value = _value(argv, i)
            if value is None:
                return None
            ns[options[a]] = value
            i += 1
            after_word = False
        elif a.startswith("-") or (words and not after_word):
            return None
        else:
            words.append(a)
            after_word = True
        i += 1
    for attr, count in positionals:
        if count == "+":
            if not words:
                return None
            ns[attr], words = words, []
        else:
            if not words:
                return None
            ns[attr], words = words[0], words[1:]
    if words:
        return None
    return SimpleNamespace(**ns)
