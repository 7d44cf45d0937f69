"""The CiA 402 state machine as dtctune walks it, against the canopen package's BaseNode402
tables (canopen.profiles.p402.State402: its statusword masks and its transitions), an
implementation written independently of this one."""
import itertools

import pytest
from canopen.profiles.p402 import State402

from dtctune import cia402

STATES = [name for name, _, _ in cia402.STATUS_PATTERNS]


def test_every_statusword_shows_the_state_canopen_decodes():
    for word in range(1 << 7):  # bits 0-6 decide; the others must not matter
        for high in (0x0000, 0xFF80):
            sw = word | high
            theirs = [s for s, (mask, value) in State402.SW_MASK.items() if sw & mask == value]
            assert cia402.state_of(sw) == (theirs[0] if theirs else None), hex(sw)


def test_each_controlword_sent_is_a_transition_canopen_knows():
    """Every step dtctune takes, from every state to every target, is a transition of
    State402.TRANSITIONTABLE with the same controlword, and leads where it says."""
    for state, target in itertools.product(STATES, set(cia402.TARGETS.values())):
        code = cia402.next_controlword(state, target)
        if code is None:
            continue
        nxt = [b for (a, b), c in State402.TRANSITIONTABLE.items() if a == state and c == code]
        assert nxt, "%s -> controlword 0x%02X: no such transition in CiA 402" % (state, code)


def _walk(state, target):
    """The states dtctune's steps pass through (the drive taking each transition)."""
    path = [state]
    for _ in range(6):
        code = cia402.next_controlword(state, target)
        if code is None:
            return path
        (state,) = [b for (a, b), c in State402.TRANSITIONTABLE.items() if a == state and c == code]
        path.append(state)
    raise AssertionError("no end: %s" % path)


@pytest.mark.parametrize("start", [s for s in STATES if s not in (cia402.NOT_READY, cia402.FAULT_REACTION)])
def test_enable_follows_canopens_path_to_operation_enabled(start):
    """BaseNode402 reaches OPERATION ENABLED through NEXTSTATE2ANY: dtctune passes the same
    states (a quick stop ends through SWITCH ON DISABLED, a fault through its reset)."""
    theirs = [start]
    while theirs[-1] != cia402.OPERATION_ENABLED:
        nxt = [v for k, v in State402.NEXTSTATE2ANY.items() if theirs[-1] == k or (isinstance(k, tuple) and theirs[-1] in k)]
        theirs.append(nxt[0])
    assert _walk(start, cia402.OPERATION_ENABLED) == theirs


def test_every_target_is_reached_from_every_state_but_a_quick_stop_of_a_stopped_drive():
    for state, target in itertools.product(STATES, set(cia402.TARGETS.values())):
        if state in (cia402.NOT_READY, cia402.FAULT_REACTION):
            assert cia402.next_controlword(state, target) is None  # the drive leaves these itself
            continue
        end = _walk(state, target)[-1]
        if target == cia402.QUICK_STOP_ACTIVE and state != cia402.OPERATION_ENABLED:
            assert end == state, "a quick stop must not enable a stopped drive: %s" % _walk(state, target)
        else:
            assert end == target, (state, target, _walk(state, target))
