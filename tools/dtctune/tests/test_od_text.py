"""The EDS reader's string tests (no `re` on the start-up path) against the regular expressions
they replace, on hand-picked and random strings. The helpers read ASCII digits and names only: the
replaced expressions used \\d and \\w, which also took other scripts' digits ('١٢' read as 12); the
references here are those expressions restricted to ASCII (an EDS and a command line name
objects in ASCII)."""
import random
import re

import pytest

from dtctune import od
from dtctune.errors import DtctuneError

INT_RE = re.compile(r"[+-]?(0[xX][0-9a-fA-F]+|[0-9]+)")
SECTION_RE = re.compile(r"([0-9A-Fa-f]{4})(?:[Ss]ub([0-9A-Fa-f]+))?")
ADDRESS_RE = re.compile(r"\s*(0x[0-9a-fA-F]{1,4})\s*(?:(?::|sub)\s*(\w+))?\s*", re.ASCII)
ALPHABET = "0123456789abcdefxXsSuUbB+-: _gG"


def random_strings(n, seed):
    rng = random.Random(seed)
    for _ in range(n):
        yield "".join(rng.choice(ALPHABET) for _ in range(rng.randint(0, 10)))


FIXED = ["", "0", "+12", "-0x1F", "0x", "0X1f", "1e3", "12a", "--1", "2001", "2001sub3", "2001SUB1f",
         "2001sub", "200", "20011", "1018sub0", "0x2001:3", "0x2001sub3", " 0x2001 : 3 ", "0x2001",
         "0x12345", "0x2001:", "0x2001:0x1", "0x2001:abc", "0x2001::3"]


@pytest.mark.parametrize("seed", [1, 2])
def test_int_literal_and_section_names_read_as_the_regular_expressions(seed):
    for t in FIXED + list(random_strings(20000, seed)):
        assert od._is_int_literal(t) == bool(INT_RE.fullmatch(t)), t
        m = SECTION_RE.fullmatch(t)
        ref = None if not m else (int(m.group(1), 16), None if m.group(2) is None else int(m.group(2), 16))
        assert od._section_address(t) == ref, t


@pytest.mark.parametrize("seed", [3])
def test_addresses_read_as_the_regular_expression(seed):
    for t in FIXED + list(random_strings(20000, seed)):
        m = ADDRESS_RE.fullmatch(t)
        try:
            got = od._parse_address(t)
        except DtctuneError:
            got = "error"
        if not m:
            assert got is None, t
            continue
        try:
            ref = (int(m.group(1), 16), int(m.group(2), 0) if m.group(2) else 0)
        except ValueError:
            ref = "error"  # the regular expression matched a subindex int() cannot read
        assert got == ref, t


@pytest.mark.parametrize("text,node,value", [("$NODEID+0x180", 5, 0x185), ("0x180+$NODEID", 5, 0x185),
                                             ("$nodeid+0x600", 1, 0x601), ("$NODEID", 7, 7), ("0x80", 3, 0x80)])
def test_nodeid_expressions(text, node, value):
    assert od._number(text, od.dt.UNSIGNED32, node) == value
