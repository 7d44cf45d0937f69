"""The drive's parameters as described by its EDS: finding, loading, naming, checking values.

The EDS is generated from the one parameter table (tools/params/parameters.toml) by the
build, so the names, units, ranges and access rights shown here are the table's.
"""
from __future__ import annotations

import math
import os
import struct
import sys

from .errors import DtctuneError, EXIT_USAGE


class dt:
    """CiA 301 data type codes (the EDS DataType values dtctune handles)."""
    BOOLEAN = 0x01
    INTEGER8 = 0x02
    INTEGER16 = 0x03
    INTEGER32 = 0x04
    UNSIGNED8 = 0x05
    UNSIGNED16 = 0x06
    UNSIGNED32 = 0x07
    REAL32 = 0x08
    VISIBLE_STRING = 0x09
    OCTET_STRING = 0x0A
    UNICODE_STRING = 0x0B
    DOMAIN = 0x0F
    REAL64 = 0x11
    INTEGER64 = 0x15
    UNSIGNED64 = 0x1B
    FLOAT_TYPES = (REAL32, REAL64)


_STRUCTS = {
    dt.BOOLEAN: struct.Struct("<?"), dt.INTEGER8: struct.Struct("<b"), dt.INTEGER16: struct.Struct("<h"),
    dt.INTEGER32: struct.Struct("<l"), dt.INTEGER64: struct.Struct("<q"), dt.UNSIGNED8: struct.Struct("<B"),
    dt.UNSIGNED16: struct.Struct("<H"), dt.UNSIGNED32: struct.Struct("<L"), dt.UNSIGNED64: struct.Struct("<Q"),
    dt.REAL32: struct.Struct("<f"), dt.REAL64: struct.Struct("<d"),
}


class Var:
    """One EDS variable (a VAR object, or a sub-index of an ARRAY/RECORD), as dtctune needs it.

    Read straight from the EDS text in one pass (see `parse_eds`): no canopen import, so the
    commands start fast. (A plain class: dataclasses and typing cost start-up time.)"""

    __slots__ = ("index", "subindex", "name", "data_type", "access_type", "default", "min", "max",
                 "factor", "unit", "description", "value_descriptions")

    def __init__(self, index: int, subindex: int, name: str, data_type: int, access_type: str = "rw",
                 unit: str = "", description: str = ""):
        self.index = index
        self.subindex = subindex
        self.name = name
        self.data_type = data_type
        self.access_type = access_type
        self.default = None
        self.min = None
        self.max = None
        self.factor = 1.0
        self.unit = unit
        self.description = description
        self.value_descriptions = {}

    def __repr__(self) -> str:
        return "Var(%s)" % ", ".join("%s=%r" % (k, getattr(self, k)) for k in self.__slots__)

    @property
    def readable(self) -> bool:
        return "r" in self.access_type or self.access_type == "const"

    @property
    def writable(self) -> bool:
        return "w" in self.access_type

    def decode_raw(self, data: bytes):
        """Bytes on the bus -> value (numbers, str for strings, bytes for domains)."""
        if self.data_type == dt.VISIBLE_STRING:
            return bytes(data).decode("ascii", errors="ignore").rstrip("\x00")
        if self.data_type == dt.UNICODE_STRING:
            return bytes(data).decode("utf_16_le", errors="ignore").rstrip("\x00")
        st = _STRUCTS.get(self.data_type)
        if st is None:
            return bytes(data)
        if len(data) < st.size:
            raise ValueError("%d bytes, %d expected" % (len(data), st.size))
        return st.unpack(bytes(data[:st.size]))[0]

    def encode_raw(self, value) -> bytes:
        if isinstance(value, (bytes, bytearray)):
            return bytes(value)
        if self.data_type == dt.VISIBLE_STRING:
            return str(value).encode("ascii")
        if self.data_type == dt.UNICODE_STRING:
            return str(value).encode("utf_16_le")
        st = _STRUCTS.get(self.data_type)
        if st is None:
            raise TypeError("no encoding for data type 0x%04X" % self.data_type)
        if self.data_type not in dt.FLOAT_TYPES and self.data_type != dt.BOOLEAN:
            value = int(value)
        return st.pack(value)


# Where the build puts the EDS, relative to the repository root. (Paths are plain strings
# here: pathlib alone costs ~0.1 s of start-up inside User-Mode Linux.)
REPO_EDS = os.path.join("build", "host", "drive.eds")
PACKAGED_EDS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data", "drive.eds")


_INT_RANGES = {
    dt.BOOLEAN: (0, 1),
    dt.INTEGER8: (-(1 << 7), (1 << 7) - 1),
    dt.INTEGER16: (-(1 << 15), (1 << 15) - 1),
    dt.INTEGER32: (-(1 << 31), (1 << 31) - 1),
    dt.INTEGER64: (-(1 << 63), (1 << 63) - 1),
    dt.UNSIGNED8: (0, (1 << 8) - 1),
    dt.UNSIGNED16: (0, (1 << 16) - 1),
    dt.UNSIGNED32: (0, (1 << 32) - 1),
    dt.UNSIGNED64: (0, (1 << 64) - 1),
}
_TYPE_NAMES = {
    dt.BOOLEAN: "BOOLEAN", dt.INTEGER8: "INTEGER8", dt.INTEGER16: "INTEGER16",
    dt.INTEGER32: "INTEGER32", dt.INTEGER64: "INTEGER64", dt.UNSIGNED8: "UNSIGNED8",
    dt.UNSIGNED16: "UNSIGNED16", dt.UNSIGNED32: "UNSIGNED32", dt.UNSIGNED64: "UNSIGNED64",
    dt.REAL32: "REAL32", dt.REAL64: "REAL64", dt.VISIBLE_STRING: "VISIBLE_STRING",
    dt.OCTET_STRING: "OCTET_STRING", dt.UNICODE_STRING: "UNICODE_STRING", dt.DOMAIN: "DOMAIN",
}


def repo_root() -> Optional[str]:
    """The repository this package sits in (tools/dtctune/ -> repo), if it is one."""
    here = os.path.dirname(os.path.realpath(__file__))
    root = os.path.dirname(os.path.dirname(here))
    if os.path.isdir(os.path.join(root, "tools", "dtctune")) and os.path.isfile(os.path.join(root, "CMakeLists.txt")):
        return root
    return None


def eds_candidates() -> List[str]:
    """Where the EDS is looked for when --eds is not given, in order."""
    out: List[str] = []
    env = os.environ.get("DTCTUNE_EDS")
    if env:
        out.append(env)
    root = repo_root()
    if root is not None:
        out.append(os.path.join(root, REPO_EDS))
    # The current directory or one of its parents may be a checkout of the project.
    d = os.getcwd()
    while True:
        if os.path.isdir(os.path.join(d, "tools", "params")) or os.path.isfile(os.path.join(d, REPO_EDS)):
            out.append(os.path.join(d, REPO_EDS))
            break
        parent = os.path.dirname(d)
        if parent == d:
            break
        d = parent
    out.append(os.path.join(sys.prefix, "share", "dtctune", "drive.eds"))
    # The EDS this version of dtctune was released with (tools/dtctune/data, kept equal to the
    # table's by ctest tools.generated_files_current): the drive's signature decides whether it fits.
    out.append(PACKAGED_EDS)
    seen, unique = set(), []
    for p in out:
        key = os.path.realpath(p) if os.path.exists(p) else p
        if key not in seen:
            seen.add(key)
            unique.append(p)
    return unique


def find_eds(explicit: Optional[str]) -> str:
    """The EDS to use: --eds PATH if given (it must exist), else the first candidate found."""
    if explicit:
        p = str(explicit)
        if not os.path.isfile(p):
            raise DtctuneError("EDS file not found: %s" % p, EXIT_USAGE)
        return p
    cands = eds_candidates()
    for p in cands:
        if os.path.isfile(p):
            return p
    raise DtctuneError(
        "no EDS found (looked for %s); build it with `cmake --build --preset host` "
        "or pass --eds PATH" % ", ".join(cands), EXIT_USAGE)


class Param:
    """One accessible value of the drive: an EDS variable (or a sub-index of an array/record)."""

    __slots__ = ("name", "var")

    def __init__(self, name: str, var: Var):
        self.name = name
        self.var = var

    def __repr__(self) -> str:
        return "Param(%r, %s)" % (self.name, self.address)

    @property
    def index(self) -> int:
        return self.var.index

    @property
    def subindex(self) -> int:
        return self.var.subindex

    @property
    def address(self) -> str:
        return "0x%04X:%d" % (self.index, self.subindex)

    @property
    def unit(self) -> str:
        return getattr(self.var, "unit", "") or ""

    @property
    def factor(self) -> float:
        return float(getattr(self.var, "factor", 1) or 1)

    @property
    def description(self) -> str:
        return getattr(self.var, "description", "") or ""

    @property
    def type_name(self) -> str:
        return _TYPE_NAMES.get(self.var.data_type, "type 0x%04X" % self.var.data_type)

    @property
    def access(self) -> str:
        return self.var.access_type

    @property
    def writable(self) -> bool:
        return self.var.writable

    @property
    def readable(self) -> bool:
        return self.var.readable

    @property
    def is_numeric(self) -> bool:
        return self.var.data_type in _INT_RANGES or self.var.data_type in dt.FLOAT_TYPES

    @property
    def is_float(self) -> bool:
        return self.var.data_type in dt.FLOAT_TYPES

    # ---- limits, in raw (transmitted) units
    def raw_limits(self) -> tuple:
        """(min, max) the drive accepts, raw units: the EDS limits within the type's range."""
        lo, hi = _INT_RANGES.get(self.var.data_type, (None, None))
        if self.var.data_type == dt.REAL32:
            lo, hi = -3.4028234663852886e38, 3.4028234663852886e38
        if self.var.min is not None:
            lo = self.var.min if lo is None else max(lo, self.var.min)
        if self.var.max is not None:
            hi = self.var.max if hi is None else min(hi, self.var.max)
        return lo, hi

    def has_eds_range(self) -> bool:
        return self.var.min is not None or self.var.max is not None

    # ---- physical <-> raw
    def to_phys(self, raw):
        if isinstance(raw, (int, float)) and not isinstance(raw, bool) and self.factor != 1:
            return raw * self.factor
        return raw

    def to_raw(self, phys: Number) -> Number:
        """Physical value -> the number sent (integers rounded to the nearest step)."""
        if self.factor != 1:
            phys = phys / self.factor
        if self.is_float:
            return float(phys)
        r = round(phys)
        if abs(r - phys) > 1e-6 * max(1.0, abs(phys)):
            step = self.factor
            raise DtctuneError("%s: %s is not a multiple of the step %g%s"
                               % (self.name, _fmt_num(phys * self.factor), step, _unit_suffix(self.unit)))
        return int(r)

    def format(self, raw) -> str:
        """A raw value as text in physical units (no unit)."""
        v = self.to_phys(raw)
        if self.is_float and isinstance(v, int) and not isinstance(v, bool):
            v = float(v)
        if isinstance(v, float):
            return _fmt_num(v)
        if isinstance(v, (bytes, bytearray)):
            return v.hex() if len(v) <= 16 else "<%d bytes>" % len(v)
        return str(v)

    def format_range(self) -> str:
        lo, hi = (self.var.min, self.var.max)
        if lo is None and hi is None:
            return ""
        lo_s = "" if lo is None else self.format(lo)
        hi_s = "" if hi is None else self.format(hi)
        return "%s..%s" % (lo_s, hi_s)

    # ---- text -> value
    def parse(self, text: str):
        """Parse a value typed by the user (physical units) into the raw value to send."""
        t = text.strip()
        code = self.var.data_type
        if code == dt.BOOLEAN:
            low = t.lower()
            if low in ("1", "true", "on", "yes"):
                return True
            if low in ("0", "false", "off", "no"):
                return False
            raise DtctuneError("%s: '%s' is not a boolean (use 0/1, true/false)" % (self.name, text))
        if code in _INT_RANGES or code in dt.FLOAT_TYPES:
            # Value descriptions (e.g. controller names) are accepted in place of numbers.
            descs = getattr(self.var, "value_descriptions", {}) or {}
            for k, d in descs.items():
                if d.lower() == t.lower():
                    return k
            try:
                if code in _INT_RANGES and self.factor == 1 and _is_int_literal(t):
                    v: Number = int(t, 0)
                else:
                    v = float(t)
            except ValueError:
                raise DtctuneError("%s: '%s' is not a number" % (self.name, text)) from None
            if isinstance(v, float) and not math.isfinite(v):
                raise DtctuneError("%s: '%s' is not a finite number" % (self.name, text))
            return self.to_raw(v)
        if code == dt.VISIBLE_STRING:
            return t
        raise DtctuneError("%s: values of type %s cannot be set from the command line"
                           % (self.name, self.type_name))

    def check(self, raw) -> None:
        """Refuse, before sending, a value the drive would refuse: read-only or out of range."""
        if not self.writable:
            raise DtctuneError("%s is read-only" % self.name)
        if isinstance(raw, bool) or not isinstance(raw, (int, float)):
            return
        lo, hi = self.raw_limits()
        if self.var.data_type == dt.REAL32 and lo is not None and hi is not None:
            # Compare what the drive will see: the value rounded to single precision.
            raw = struct.unpack("<f", struct.pack("<f", raw))[0]
        if (lo is not None and raw < lo) or (hi is not None and raw > hi):
            raise DtctuneError("%s: %s%s is outside the range %s%s; not sent"
                               % (self.name, self.format(raw), _unit_suffix(self.unit),
                                  self.format_range() or "%s..%s" % (self.format(lo), self.format(hi)),
                                  _unit_suffix(self.unit)))


def _fmt_num(v: Number) -> str:
    if isinstance(v, float):
        if v == int(v) and abs(v) < 1e15:
            return "%.1f" % v if abs(v) < 1e6 else "%.7g" % v
        return "%.7g" % v
    return str(v)


def _unit_suffix(unit: str) -> str:
    return " " + unit if unit else ""


class Dictionary:
    """The loaded EDS: every readable value under a unique name."""

    def __init__(self, path, node_id: int):
        self.path = os.fspath(path)
        self.node_id = node_id
        try:
            with open(self.path, encoding="utf-8", errors="replace") as f:
                text = f.read()
        except OSError as e:
            raise DtctuneError("cannot read EDS %s: %s" % (self.path, e.strerror or e), EXIT_USAGE) from None
        try:
            objects = parse_eds(text, node_id)
        except (ValueError, KeyError) as e:
            raise DtctuneError("cannot read EDS %s: %s" % (self.path, _one_line(e)), EXIT_USAGE) from None
        if not objects:
            raise DtctuneError("EDS %s describes no objects" % self.path, EXIT_USAGE)
        # index -> {subindex: Var}; the indexes the EDS lists
        self.objects: Dict[int, Dict[int, Var]] = {}
        self.params: List[Param] = []
        self._by_name: Dict[str, Param] = {}
        self._by_addr: Dict[tuple, Param] = {}
        members = []
        for index in sorted(objects):
            obj_name, is_var, subs = objects[index]
            self.objects[index] = subs
            if is_var:
                if 0 in subs:
                    members.append((None, subs[0]))
            else:
                # sub-index 0 is the "number of entries" of an array or record
                members.extend((obj_name, subs[k]) for k in sorted(subs) if k != 0)
        # The parameter table gives every value a unique name; a member whose name is not
        # unique on its own (e.g. of a hand-written EDS) is qualified by its object's name.
        counts: Dict[str, int] = {}
        for _, var in members:
            counts[var.name.lower()] = counts.get(var.name.lower(), 0) + 1
        for parent, var in members:
            name = var.name
            if parent is not None and counts[name.lower()] > 1:
                name = "%s.%s" % (parent, name)
            self._add(name, var)

    def has_object(self, index: int) -> bool:
        return index in self.objects

    def default(self, index: int, subindex: int):
        """The EDS DefaultValue of index:subindex (with $NODEID applied), or None."""
        var = self.objects.get(index, {}).get(subindex)
        return None if var is None else var.default

    def _add(self, name: str, var: Var) -> None:
        p = Param(name, var)
        key = name.lower()
        if key in self._by_name:  # keep names unique: qualify the later one by its address
            p = Param("%s@%s" % (name, p.address), var)
            key = p.name.lower()
        self.params.append(p)
        self._by_name[key] = p
        self._by_addr[(var.index, var.subindex)] = p

    def get_var(self, index: int, subindex: int) -> Optional[Var]:
        p = self._by_addr.get((index, subindex))
        return p.var if p else None

    def lookup(self, name: str) -> Param:
        """By name (case-insensitive) or address (`0x2001:3`, `0x2001sub3`, `0x2001`)."""
        p = self._by_name.get(name.strip().lower())
        if p is not None:
            return p
        addr = _parse_address(name)
        if addr is not None:
            p = self._by_addr.get(addr)
            if p is not None:
                return p
            raise DtctuneError("no object %s in the EDS %s" % (name.strip(), self.path))
        import difflib  # only for this message: not on every command's start-up path
        close = difflib.get_close_matches(name.lower(), list(self._by_name), n=3, cutoff=0.6)
        hint = "; did you mean %s?" % ", ".join(self._by_name[c].name for c in close) if close else \
            "; `dtctune list` shows the names"
        raise DtctuneError("unknown parameter '%s'%s" % (name, hint))

    def select(self, all_objects: bool = False, pattern: Optional[str] = None) -> Iterable[Param]:
        """Parameters for `list`: the manufacturer and device profile areas unless all_objects."""
        for p in self.params:
            if not all_objects and p.index < 0x2000:
                continue
            if p.var.data_type == dt.DOMAIN and not all_objects:
                continue
            if pattern and pattern.lower() not in p.name.lower():
                continue
            yield p


# Plain string tests instead of regular expressions: importing `re` costs 0.07 s of every
# command's start-up inside User-Mode Linux (tools/dtctune_bench.py startup).
_HEX = frozenset("0123456789abcdefABCDEF")


def _is_hex(t: str) -> bool:
    return bool(t) and all(c in _HEX for c in t)


def _is_int_literal(t: str) -> bool:
    """[+-]?(0x<hex>|<decimal digits>): what int(t, 0) reads as an integer."""
    u = t[1:] if t[:1] in ("+", "-") else t
    if u[:2] in ("0x", "0X"):
        return _is_hex(u[2:])
    return u.isascii() and u.isdigit()


def _parse_address(name: str) -> Optional[Tuple[int, int]]:
    """(index, subindex) of `0x2001:3`, `0x2001sub3` or `0x2001` (1-4 hex digits, subindex in
    any int() notation), or None when name is not an address."""
    t = name.strip()
    if not t.startswith("0x"):
        return None
    head, sep, sub = t.partition(":")
    if not sep:
        head, sep, sub = t.partition("sub")
    digits = head.strip()[2:]
    if not 1 <= len(digits) <= 4 or not _is_hex(digits):
        return None
    if not sep:
        return int(digits, 16), 0
    sub = sub.strip()
    if not sub or not all(c.isascii() and (c.isalnum() or c == "_") for c in sub):
        return None
    try:
        return int(digits, 16), int(sub, 0)
    except ValueError:
        raise DtctuneError("'%s': the subindex '%s' is not a number" % (name.strip(), sub)) from None


def _section_address(name: str) -> Optional[Tuple[int, Optional[int]]]:
    """EDS section names: '2001' -> (0x2001, None), '2001sub3' -> (0x2001, 3) (hex), else None."""
    if len(name) < 4 or not _is_hex(name[:4]):
        return None
    if len(name) == 4:
        return int(name, 16), None
    if name[4:5] in ("s", "S") and name[5:7] == "ub" and _is_hex(name[7:]):
        return int(name[:4], 16), int(name[7:], 16)
    return None


def _ini_sections(text: str) -> Dict[str, Dict[str, str]]:
    """The sections of an INI text (as EDS files are written): {section: {key: value}}.
    Keys keep their case; a ';' starting a line, or after blanks, starts a comment."""
    out: Dict[str, Dict[str, str]] = {}
    cur: Optional[Dict[str, str]] = None
    for line in text.splitlines():
        line = line.strip()
        if not line or line[0] in ";#":
            continue
        if line[0] == "[":
            end = line.find("]")
            if end < 0:
                raise ValueError("bad section line '%s'" % line)
            cur = out.setdefault(line[1:end].strip(), {})
            continue
        key, sep, value = line.partition("=")
        if not sep:
            raise ValueError("line without '=': '%s'" % line)
        if cur is None:
            raise ValueError("'%s' before the first section" % line)
        for c in (" ;", "\t;"):
            k = value.find(c)
            if k >= 0:
                value = value[:k]
        cur[key.strip()] = value.strip()
    return out


def _number(text: str, data_type: int, node_id: Optional[int]):
    t = text.strip()
    if data_type in dt.FLOAT_TYPES:
        return float(t)
    if "$NODEID" in t.upper():
        k = t.upper().find("$NODEID")  # "$NODEID+0x180", "0x180+$NODEID": drop it and its "+"
        before, after = t[:k], t[k + len("$NODEID"):]
        t = (before[:-1] if before.endswith("+") else before) + (after[1:] if after.startswith("+") else after)
        t = t or "0"
        return int(t, 0) + (node_id or 0)
    return int(t, 0)


def parse_eds(text: str, node_id: Optional[int]):
    """One pass over the EDS: {index: (object name, is a VAR, {subindex: Var})}.
    Raises ValueError / KeyError on what cannot be read."""
    secs = _ini_sections(text)
    objects: Dict[int, tuple] = {}
    for name, sec in secs.items():
        addr = _section_address(name)
        if addr is None or addr[1] is not None:
            continue
        index = addr[0]
        otype = int(sec.get("ObjectType", "0x7") or "0x7", 0)
        pname = sec.get("ParameterName", "0x%04X" % index)
        subs: Dict[int, Var] = {}
        if otype in (0x7, 0x2):          # VAR (DEFTYPE too)
            subs[0] = _var(sec, index, 0, node_id)
            objects[index] = (pname, True, subs)
        elif otype in (0x8, 0x9):        # ARRAY, RECORD: members in [xxxxsubN]
            objects[index] = (pname, False, subs)
        # DOMAIN definitions etc.: not values dtctune reads
    for name, sec in secs.items():
        addr = _section_address(name)
        if addr is None or addr[1] is None:
            continue
        index, sub = addr
        if index in objects and not objects[index][1]:
            objects[index][2][sub] = _var(sec, index, sub, node_id)
    return objects


def _var(sec: Dict[str, str], index: int, sub: int, node_id: Optional[int]) -> Var:
    where = "0x%04X:%d" % (index, sub)
    try:
        data_type = int(sec["DataType"], 0)
    except KeyError:
        raise ValueError("%s has no DataType" % where) from None
    except ValueError:
        raise ValueError("%s: DataType '%s' is not a number" % (where, sec["DataType"])) from None
    var = Var(index, sub, sec.get("ParameterName", where), data_type,
              access_type=sec.get("AccessType", "rw").strip().lower() or "rw",
              unit=sec.get("Unit", ""), description=sec.get("Description", ""))
    if sec.get("Factor"):
        var.factor = float(sec["Factor"])
    numeric = data_type in _STRUCTS
    for key, attr in (("LowLimit", "min"), ("HighLimit", "max")):
        if numeric and sec.get(key):
            try:
                setattr(var, attr, _number(sec[key], data_type, node_id))
            except ValueError:
                raise ValueError("%s: %s '%s' is not a number" % (where, key, sec[key])) from None
    text = sec.get("DefaultValue")
    if text is not None:
        if numeric and text.strip():
            try:
                var.default = _number(text, data_type, node_id)
            except ValueError:
                var.default = None
        elif not numeric:
            var.default = text
    return var


def _one_line(e: BaseException) -> str:
    s = str(e) or e.__class__.__name__
    return " ".join(s.split())
