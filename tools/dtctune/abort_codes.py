"""SDO abort codes of CiA 301, in words a drive engineer can act on."""

_WORDS = {
    0x05030000: "toggle bit not alternated",
    0x05040000: "SDO transfer timed out",
    0x05040001: "unknown or invalid SDO command",
    0x05040002: "invalid block size",
    0x05040003: "invalid block sequence number",
    0x05040004: "block CRC error",
    0x05040005: "out of memory",
    0x06010000: "this kind of access to the object is not supported",
    0x06010001: "the object is write-only",
    0x06010002: "the object is read-only",
    0x06020000: "no such object in the drive's object dictionary",
    0x06040041: "the object cannot be mapped into a PDO",
    0x06040042: "the mapped objects would not fit into the PDO",
    0x06040043: "parameters incompatible",
    0x06040047: "internal incompatibility in the drive",
    0x06060000: "hardware error while accessing the object",
    0x06070010: "wrong data length for this object",
    0x06070012: "data too long for this object",
    0x06070013: "data too short for this object",
    0x06090011: "no such sub-index",
    0x06090030: "value not allowed for this parameter",
    0x06090031: "value too high",
    0x06090032: "value too low",
    0x06090036: "maximum would be below minimum",
    0x060A0023: "resource not available",
    0x08000000: "general error",
    0x08000020: "the drive cannot store or apply the data",
    0x08000021: "the drive cannot store or apply the data: under local control",
    0x08000022: "not allowed in the drive's present state (e.g. while running)",
    0x08000023: "no object dictionary available",
    0x08000024: "no data available",
}


def describe(code: int) -> str:
    """`value too high (0x06090031)`; unknown codes are shown by number."""
    words = _WORDS.get(code)
    if words is None:
        return "abort code 0x%08X (not a CiA 301 code)" % code
    return "%s (0x%08X)" % (words, code)
