"""The CiA 402 power drive state machine as the PC sees it: the state a statusword (0x6041)
shows, and the controlword (0x6040) that takes the drive one transition nearer a wanted state.

The statusword patterns and the controlword commands are those of CiA 402 part 2 (IEC
61800-7-201, the "device control" state machine); `dtctune state TARGET` walks the drive to
TARGET one transition at a time, waiting for the statusword after each, as a master does
(the canopen package's BaseNode402 walks the same table; tests/test_cia402.py compares them).
"""
from __future__ import annotations

from typing import Optional

# (mask, value) of the statusword's bits 0-3, 5 and 6 for each state
NOT_READY = "NOT READY TO SWITCH ON"
SWITCH_ON_DISABLED = "SWITCH ON DISABLED"
READY = "READY TO SWITCH ON"
SWITCHED_ON = "SWITCHED ON"
OPERATION_ENABLED = "OPERATION ENABLED"
QUICK_STOP_ACTIVE = "QUICK STOP ACTIVE"
FAULT_REACTION = "FAULT REACTION ACTIVE"
FAULT = "FAULT"

STATUS_PATTERNS = (
    (NOT_READY, 0x4F, 0x00),
    (SWITCH_ON_DISABLED, 0x4F, 0x40),
    (READY, 0x6F, 0x21),
    (SWITCHED_ON, 0x6F, 0x23),
    (OPERATION_ENABLED, 0x6F, 0x27),
    (QUICK_STOP_ACTIVE, 0x6F, 0x07),
    (FAULT_REACTION, 0x4F, 0x0F),
    (FAULT, 0x4F, 0x08),
)

# controlword commands (bits 0-3 and 7)
CW_SHUTDOWN = 0x06          # -> READY TO SWITCH ON
CW_SWITCH_ON = 0x07         # -> SWITCHED ON (from OPERATION ENABLED: disable operation)
CW_ENABLE_OPERATION = 0x0F  # -> OPERATION ENABLED
CW_DISABLE_VOLTAGE = 0x00   # -> SWITCH ON DISABLED
CW_QUICK_STOP = 0x02        # -> QUICK STOP ACTIVE (then SWITCH ON DISABLED once stopped)
CW_FAULT_RESET = 0x80       # rising edge of bit 7: FAULT -> SWITCH ON DISABLED

# What `dtctune state` accepts: the command names of the users and the state names.
TARGETS = {
    "enable": OPERATION_ENABLED,
    "operation-enabled": OPERATION_ENABLED,
    "switch-on": SWITCHED_ON,
    "switched-on": SWITCHED_ON,
    "shutdown": READY,
    "ready-to-switch-on": READY,
    "disable": SWITCH_ON_DISABLED,
    "switch-on-disabled": SWITCH_ON_DISABLED,
    "quick-stop": QUICK_STOP_ACTIVE,
    "fault-reset": SWITCH_ON_DISABLED,
}


def state_of(statusword: int) -> Optional[str]:
    """The state a statusword shows, or None for a pattern CiA 402 does not define."""
    for name, mask, value in STATUS_PATTERNS:
        if statusword & mask == value:
            return name
    return None


# The one transition from `state` towards `target` (None: nothing to send, wait or done).
_TOWARDS_ENABLED = {
    SWITCH_ON_DISABLED: CW_SHUTDOWN,
    READY: CW_SWITCH_ON,
    SWITCHED_ON: CW_ENABLE_OPERATION,
    QUICK_STOP_ACTIVE: CW_DISABLE_VOLTAGE,  # the drive leaves it by itself once stopped; this ends it
    FAULT: CW_FAULT_RESET,
}


def next_controlword(state: str, target: str) -> Optional[int]:
    """The controlword of the next transition on the way from `state` to `target`: up the
    enable chain (SWITCH ON DISABLED -> READY -> SWITCHED ON -> OPERATION ENABLED), down by
    the direct transitions CiA 402 has (disable voltage, shutdown, disable operation, quick
    stop), out of FAULT by a fault reset. None when `state` is `target`, a state the drive
    leaves by itself (NOT READY TO SWITCH ON, FAULT REACTION ACTIVE), or a quick stop asked of
    a drive whose operation is not enabled."""
    if state == target or state in (NOT_READY, FAULT_REACTION):
        return None
    if target == QUICK_STOP_ACTIVE:
        # only from OPERATION ENABLED (transition 11): a drive not enabled has nothing to stop,
        # and enabling it to stop it again would start the motor
        return CW_QUICK_STOP if state == OPERATION_ENABLED else None
    if state == FAULT:
        return CW_FAULT_RESET
    if target == SWITCH_ON_DISABLED:
        return CW_DISABLE_VOLTAGE
    if target == READY:
        return CW_DISABLE_VOLTAGE if state == QUICK_STOP_ACTIVE else CW_SHUTDOWN
    if target == SWITCHED_ON:
        if state == OPERATION_ENABLED:
            return CW_SWITCH_ON  # disable operation
        return _TOWARDS_ENABLED[state]
    if target == OPERATION_ENABLED:
        return _TOWARDS_ENABLED[state]
    raise ValueError("unknown target state %r" % target)
