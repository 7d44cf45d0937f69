"""The drive's parameters as described by its EDS: finding, loading, naming, checking values.

The EDS is generated from the one parameter table (tools/params/parameters.toml) by the
build, so the names, units, ranges and access rights shown here are the table's.
"""
from __future__ import annotations

import difflib
import logging
import math
import os
import re
import struct
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Iterable, List, Optional, Union

from canopen import objectdictionary as cood
from canopen.objectdictionary import datatypes as dt

from .errors import DtctuneError, EXIT_USAGE

# Where the build puts the EDS, relative to the repository root.
REPO_EDS = Path("build") / "host" / "drive.eds"

Number = Union[int, float]

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


def repo_root() -> Optional[Path]:
    """The repository this package sits in (tools/dtctune/ -> repo), if it is one."""
    here = Path(__file__).resolve().parent
    root = here.parent.parent
    if (root / "tools" / "dtctune").is_dir() and (root / "CMakeLists.txt").is_file():
        return root
    return None


def eds_candidates() -> List[Path]:
    """Where the EDS is looked for when --eds is not given, in order."""
    out: List[Path] = []
    env = os.environ.get("DTCTUNE_EDS")
    if env:
        out.append(Path(env))
    root = repo_root()
    if root is not None:
        out.append(root / REPO_EDS)
    # The current directory or one of its parents may be a checkout of the project.
    cwd = Path.cwd()
    for d in [cwd, *cwd.parents]:
        if (d / "tools" / "params").is_dir() or (d / REPO_EDS).is_file():
            out.append(d / REPO_EDS)
            break
    out.append(Path(sys.prefix) / "share" / "dtctune" / "drive.eds")
    seen, unique = set(), []
    for p in out:
        key = str(p.resolve()) if p.exists() else str(p)
        if key not in seen:
            seen.add(key)
            unique.append(p)
    return unique


def find_eds(explicit: Optional[str]) -> Path:
    """The EDS to use: --eds PATH if given (it must exist), else the first candidate found."""
    if explicit:
        p = Path(explicit)
        if not p.is_file():
            raise DtctuneError("EDS file not found: %s" % p, EXIT_USAGE)
        return p
    cands = eds_candidates()
    for p in cands:
        if p.is_file():
            return p
    raise DtctuneError(
        "no EDS found (looked for %s); build it with `cmake --build --preset host` "
        "or pass --eds PATH" % ", ".join(str(p) for p in cands), EXIT_USAGE)


@dataclass
class Param:
    """One accessible value of the drive: an EDS variable (or a sub-index of an array/record)."""

    name: str
    var: cood.ODVariable

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
                if code in _INT_RANGES and self.factor == 1 and re.fullmatch(r"[+-]?(0[xX][0-9a-fA-F]+|\d+)", t):
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

    def __init__(self, path: Path, node_id: int):
        self.path = Path(path)
        self.node_id = node_id
        # canopen logs EDS oddities and its own aborts (e.g. on a timeout); we report in one line.
        logging.getLogger("canopen").setLevel(logging.CRITICAL)
        try:
            self.od = cood.import_od(str(self.path), node_id)
        except Exception as e:  # the canopen parser raises many kinds
            raise DtctuneError("cannot read EDS %s: %s" % (self.path, _one_line(e)), EXIT_USAGE) from None
        if len(self.od) == 0:
            raise DtctuneError("EDS %s describes no objects" % self.path, EXIT_USAGE)
        _fix_limits(self.od, self.path)
        self.params: List[Param] = []
        self._by_name: Dict[str, Param] = {}
        self._by_addr: Dict[tuple, Param] = {}
        members = []
        for obj in self.od.values():
            if isinstance(obj, cood.ODVariable):
                members.append((None, obj))
            else:
                # sub-index 0 is the "number of entries" of an array or record
                members.extend((obj.name, sub) for sub in obj.subindices.values() if sub.subindex != 0)
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

    def _add(self, name: str, var: cood.ODVariable) -> None:
        p = Param(name, var)
        key = name.lower()
        if key in self._by_name:  # keep names unique: qualify the later one by its address
            p = Param("%s@%s" % (name, p.address), var)
            key = p.name.lower()
        self.params.append(p)
        self._by_name[key] = p
        self._by_addr[(var.index, var.subindex)] = p

    def get_var(self, index: int, subindex: int) -> Optional[cood.ODVariable]:
        p = self._by_addr.get((index, subindex))
        return p.var if p else None

    def lookup(self, name: str) -> Param:
        """By name (case-insensitive) or address (`0x2001:3`, `0x2001sub3`, `0x2001`)."""
        p = self._by_name.get(name.strip().lower())
        if p is not None:
            return p
        m = re.fullmatch(r"\s*(0x[0-9a-fA-F]{1,4})\s*(?:(?::|sub)\s*(\w+))?\s*", name)
        if m:
            index = int(m.group(1), 16)
            sub = int(m.group(2), 0) if m.group(2) else 0
            p = self._by_addr.get((index, sub))
            if p is not None:
                return p
            raise DtctuneError("no object %s in the EDS %s" % (name.strip(), self.path))
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


def _fix_limits(od, path: Path) -> None:
    """LowLimit/HighLimit the canopen parser skipped (it reads them as integers only, so
    `HighLimit=2000.0` of a REAL32 is lost): read them again from the EDS text."""
    import configparser

    eds = configparser.RawConfigParser(inline_comment_prefixes=(";",), strict=False)
    eds.optionxform = str
    try:
        eds.read(str(path), encoding="utf-8")
    except (configparser.Error, UnicodeDecodeError, OSError):
        return
    for section in eds.sections():
        m = re.fullmatch(r"([0-9A-Fa-f]{4})(?:sub([0-9A-Fa-f]+))?", section)
        if not m:
            continue
        var = od.get_variable(int(m.group(1), 16), int(m.group(2), 16) if m.group(2) else 0)
        if var is None:
            continue
        for key, attr in (("LowLimit", "min"), ("HighLimit", "max")):
            if getattr(var, attr) is not None or not eds.has_option(section, key):
                continue
            text = eds.get(section, key).strip()
            try:
                if var.data_type in dt.FLOAT_TYPES:
                    value: Number = float(text)
                else:
                    value = int(text, 0)
            except ValueError:
                continue
            setattr(var, attr, value)


def _one_line(e: BaseException) -> str:
    s = str(e) or e.__class__.__name__
    return " ".join(s.split())
