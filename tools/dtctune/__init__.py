"""dtctune: tune the DTC drive over CANopen from a PC (python-can + canopen)."""

__version__ = "0.1.0"
