#!/usr/bin/env python3
"""Generate the drive's object dictionary, EDS, DBC and parameter reference.

One input, tools/params/parameters.toml (the single source of truth), and
these outputs (each optional on the command line):

  --c-header  dtc/param_table.h   declarations, entry ids, handler ids, PDO maps
  --c-source  param_table.c       the const entry table (offsetof bindings,
                                  compile-time type checks), PDO and EMCY tables
  --eds       drive.eds           CiA 306 EDS (loads with the Python canopen package)
  --dbc       telemetry.dbc       the telemetry TPDOs for the default node id
  --md        parameters.md       the parameter reference (docs/parameters.md)
  --check-md  PATH                exit 1 unless PATH equals the generated reference
  --check-eds PATH                exit 1 unless PATH equals the generated EDS (its modification
                                  date and time aside): dtctune's packaged copy

Standard library only (Python 3.11: tomllib). Any inconsistency in the table
(duplicate name or index, default outside the limits, a PDO longer than 8
bytes, an unknown binding ...) stops the build with "parameters.toml: <name>:
<problem>" and exit status 2; outputs are written only when all checks pass.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import struct
import sys
import zlib
import tomllib

# ---------------------------------------------------------------- data types

# name -> (EDS DataType code, size in bytes (0: variable), kind, min, max)
TYPES = {
    "BOOLEAN": (0x01, 1, "uint", 0, 1),
    "INTEGER8": (0x02, 1, "sint", -(2**7), 2**7 - 1),
    "INTEGER16": (0x03, 2, "sint", -(2**15), 2**15 - 1),
    "INTEGER32": (0x04, 4, "sint", -(2**31), 2**31 - 1),
    "UNSIGNED8": (0x05, 1, "uint", 0, 2**8 - 1),
    "UNSIGNED16": (0x06, 2, "uint", 0, 2**16 - 1),
    "UNSIGNED32": (0x07, 4, "uint", 0, 2**32 - 1),
    "REAL32": (0x08, 4, "real", -3.4028234663852886e38, 3.4028234663852886e38),
    "VISIBLE_STRING": (0x09, 0, "string", None, None),
    "DOMAIN": (0x0F, 0, "domain", None, None),
}

# C type implied by a bus type when the table gives no ctype.
DEFAULT_CTYPE = {
    "BOOLEAN": "bool",
    "INTEGER8": "i8",
    "INTEGER16": "i16",
    "INTEGER32": "i32",
    "UNSIGNED8": "u8",
    "UNSIGNED16": "u16",
    "UNSIGNED32": "u32",
    "REAL32": "float",
}

# ctype -> (co_ckind, C type for the compile-time check or None for enums)
CTYPES = {
    "float": ("CO_CK_FLOAT", "float"),
    "u8": ("CO_CK_UINT", "uint8_t"),
    "u16": ("CO_CK_UINT", "uint16_t"),
    "u32": ("CO_CK_UINT", "uint32_t"),
    "i8": ("CO_CK_SINT", "int8_t"),
    "i16": ("CO_CK_SINT", "int16_t"),
    "i32": ("CO_CK_SINT", "int32_t"),
    "bool": ("CO_CK_BOOL", "_Bool"),
    "enum": ("CO_CK_UINT", None),
}

# Bind prefix -> (co_bind, C struct type the path is a member of)
BINDS = {
    "cfg": ("DRIVE_BIND_CFG", "ctl_cfg"),
    "comm": ("CO_BIND_COMM", "co_comm_cfg"),
    "scope": ("DRIVE_BIND_SCOPE", "scope_cfg"),
    "app": ("DRIVE_BIND_APP", "drive_app_cfg"),
    "snap": ("DRIVE_BIND_SNAP", "drive_snapshot"),
    "drive": ("DRIVE_BIND_DRIVE", "drive"),
}

ERROR_REGISTER_BITS = {
    "generic": 0,
    "current": 1,
    "voltage": 2,
    "temperature": 3,
    "communication": 4,
    "profile": 5,
    "manufacturer": 7,
}

NAME_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
PATH_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\[[0-9]+\])?(\.[A-Za-z_][A-Za-z0-9_]*(\[[0-9]+\])?)*$")


class TableError(Exception):
    pass


def f32(x: float) -> float:
    """The float32 nearest to x, as a Python float (exactly representable)."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def c_float(x: float) -> str:
    """A C float literal that parses to exactly f32(x)."""
    v = f32(x)
    if v == 0.0:
        return "0.0f" if math.copysign(1.0, v) > 0 else "-0.0f"
    s = repr(v)
    if "e" not in s and "." not in s and "inf" not in s:
        s += ".0"
    return s + "f"


def fmt_num(x, kind: str) -> str:
    """A value for humans and the EDS: integers in decimal, reals as the
    shortest decimal that reads back as the same float32 (0.1, not 0.100000001)."""
    if kind == "real":
        v = f32(float(x))
        for digits in range(1, 10):
            s = repr(float(f"{v:.{digits}g}"))
            if f32(float(s)) == v:
                return s
        return repr(v)
    return str(int(x))


# ------------------------------------------------------------------- model


class Param:
    """One expanded table entry (one index/subindex)."""

    def __init__(self, **kw):
        self.__dict__.update(kw)

    @property
    def code(self) -> int:
        return TYPES[self.type][0]

    @property
    def size(self) -> int:
        return TYPES[self.type][1]

    @property
    def kind(self) -> str:
        return TYPES[self.type][2]

    @property
    def ident(self) -> str:
        return "CO_P_" + self.name.upper()


def load_table(path: str) -> dict:
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh)
    except OSError as e:
        raise TableError(f"cannot read: {e.strerror}") from e
    except tomllib.TOMLDecodeError as e:
        raise TableError(f"not valid TOML: {e}") from e


def expand_params(raw: list) -> list[Param]:
    out = []
    for n, e in enumerate(raw):
        name = e.get("name")
        where = name or f"[[param]] #{n + 1}"
        if not isinstance(name, str) or not NAME_RE.match(name):
            raise TableError(f"{where}: name must be an identifier")
        known = {"name", "index", "sub", "count", "type", "unit", "scale", "resolution", "min", "max",
                 "allowed", "default", "access", "persist", "runtime", "max_step", "pdo", "bind", "ctype",
                 "range_within", "description"}
        for key in e:
            if key not in known:
                raise TableError(f"{name}: unknown key '{key}'")
        for key in ("index", "type", "access", "bind", "description"):
            if key not in e:
                raise TableError(f"{name}: missing '{key}'")
        count = e.get("count", 1)
        if not isinstance(count, int) or not 1 <= count <= 254:
            raise TableError(f"{name}: count must be 1..254")
        default = e.get("default")
        if count > 1:
            if isinstance(default, list):
                if len(default) != count:
                    raise TableError(f"{name}: default list has {len(default)} values, count is {count}")
                defaults = default
            else:
                defaults = [default] * count
        else:
            if isinstance(default, list):
                raise TableError(f"{name}: a list default needs count")
            defaults = [default]
        sub0 = e.get("sub", 0)
        for i in range(count):
            pname = name if count == 1 else f"{name}_{i + 1}"
            bind = e["bind"].replace("{i}", str(i))
            out.append(Param(
                name=pname, base=name, index=e["index"], sub=sub0 + i, type=e["type"],
                unit=e.get("unit", ""), scale=float(e.get("scale", 1.0)),
                resolution=float(e.get("resolution", 1.0)), min=e.get("min"), max=e.get("max"),
                allowed=e.get("allowed"), default=defaults[i], access=e["access"],
                persist=bool(e.get("persist", False)), runtime=bool(e.get("runtime", False)),
                max_step=e.get("max_step", 0.0),
                pdo=bool(e.get("pdo", False)), bind=bind, ctype=e.get("ctype"),
                range_within=e.get("range_within"), description=e["description"], generated=False))
    return out


def check_param(p: Param, fn_names: set) -> None:
    if p.type not in TYPES:
        raise TableError(f"{p.name}: unknown type '{p.type}'")
    if not isinstance(p.index, int) or not 0x1000 <= p.index <= 0x9FFF:
        raise TableError(f"{p.name}: index must be 0x1000..0x9FFF")
    if not isinstance(p.sub, int) or not 0 <= p.sub <= 254:
        raise TableError(f"{p.name}: sub must be 0..254")
    if p.access not in ("ro", "rw", "const"):
        raise TableError(f"{p.name}: access must be ro, rw or const")
    if p.scale == 0 or p.resolution <= 0 or not math.isfinite(p.scale) or not math.isfinite(p.resolution):
        raise TableError(f"{p.name}: scale must be non-zero and resolution > 0")
    kind = p.kind
    lo_t, hi_t = TYPES[p.type][3], TYPES[p.type][4]
    # binding
    b = p.bind
    if b in ("const", "nodeid"):
        p.bind_kind, p.bind_struct, p.path = ("CO_BIND_CONST" if b == "const" else "CO_BIND_NODEID"), None, None
        if p.access == "rw":
            raise TableError(f"{p.name}: a constant cannot be rw")
    elif b == "errhist":
        # The device's own error history (CiA 301 0x1003): sub 0 the number of errors
        # recorded (rw: writing 0 clears), sub 1.. the errors, newest first.
        p.bind_kind, p.bind_struct, p.path = "CO_BIND_ERRHIST", None, None
        if p.index != 0x1003:
            raise TableError(f"{p.name}: bind errhist belongs to 0x1003")
    elif b.startswith("fn."):
        fn = b[3:]
        if not NAME_RE.match(fn):
            raise TableError(f"{p.name}: bad handler name '{fn}'")
        p.bind_kind, p.bind_struct, p.path = "DRIVE_BIND_FN", None, fn
        fn_names.add(fn)
    else:
        prefix, _, path = b.partition(".")
        if prefix not in BINDS or not PATH_RE.match(path or ""):
            raise TableError(f"{p.name}: bind must be const, nodeid, fn.NAME or one of "
                             f"{', '.join(k + '.PATH' for k in BINDS)}")
        p.bind_kind, p.bind_struct = BINDS[prefix]
        p.path = path
        if prefix in ("snap", "drive") and p.access == "rw":
            raise TableError(f"{p.name}: {prefix}.* bindings are read only")
    if kind in ("string", "domain"):
        if p.scale != 1.0 or p.resolution != 1.0 or p.min is not None or p.max is not None:
            raise TableError(f"{p.name}: strings and domains take no scale or limits")
        if p.access == "rw":
            raise TableError(f"{p.name}: writable strings and domains are not supported")
        if kind == "string" and p.bind_kind == "CO_BIND_CONST" and not isinstance(p.default, str):
            raise TableError(f"{p.name}: a constant string needs a string default")
        if kind == "domain" and p.bind_kind != "DRIVE_BIND_FN":
            raise TableError(f"{p.name}: a domain must be bound to a handler")
        p.ctype_name = None
        return
    # numbers
    if p.default is None:
        raise TableError(f"{p.name}: missing default")
    # An integer on the bus with a scale binds a float field (e.g. rpm <-> rad/s).
    scaled = p.scale != 1.0 or p.resolution != 1.0
    ctype = p.ctype or ("float" if scaled else DEFAULT_CTYPE[p.type])
    if ctype not in CTYPES:
        raise TableError(f"{p.name}: unknown ctype '{ctype}'")
    p.ctype_name = ctype
    if kind != "real" and ctype != "float" and (p.scale != 1.0 or p.resolution != 1.0):
        raise TableError(f"{p.name}: an integer bound to an integer field cannot be scaled")
    if kind == "real" and ctype != "float":
        raise TableError(f"{p.name}: REAL32 must bind a float field")
    for key in ("min", "max", "default"):
        v = getattr(p, key)
        if v is None:
            continue
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise TableError(f"{p.name}: {key} must be a number")
        if kind != "real" and not isinstance(v, int):
            raise TableError(f"{p.name}: {key} of an integer type must be an integer")
        if not (lo_t <= v <= hi_t):
            raise TableError(f"{p.name}: {key} {v} outside the range of {p.type}")
    if p.access == "rw" and (p.min is None) != (p.max is None):
        raise TableError(f"{p.name}: give both min and max or neither")
    if p.min is not None and p.min > p.max:
        raise TableError(f"{p.name}: min > max")
    if p.min is not None and not (p.min <= p.default <= p.max):
        raise TableError(f"{p.name}: default {p.default} outside [{p.min}, {p.max}]")
    if p.allowed is not None:
        if kind == "real" or not isinstance(p.allowed, list) or not p.allowed or \
                not all(isinstance(a, int) and not isinstance(a, bool) for a in p.allowed):
            raise TableError(f"{p.name}: allowed must be a list of integers")
        if p.default not in p.allowed:
            raise TableError(f"{p.name}: default not in allowed")
        if len(p.allowed) > 32:
            raise TableError(f"{p.name}: at most 32 allowed values")
    if p.persist and p.access != "rw":
        raise TableError(f"{p.name}: only rw parameters can persist")
    ms = getattr(p, "max_step", 0.0)
    if isinstance(ms, bool) or not isinstance(ms, (int, float)) or not 0.0 <= ms <= 10.0:
        raise TableError(f"{p.name}: max_step must be a number 0..10 (a fraction of the present value)")
    if ms and (not p.runtime or ctype != "float"):
        raise TableError(f"{p.name}: max_step needs runtime = true and a float field")
    if kind == "real":
        p.raw_min = None if p.min is None else f32(p.min)
        p.raw_max = None if p.max is None else f32(p.max)
        p.raw_def = f32(p.default)
    else:
        p.raw_min, p.raw_max, p.raw_def = p.min, p.max, p.default


class Table:
    def __init__(self, data: dict):
        self.device = data.get("device", {})
        for key in ("vendor_name", "vendor_id", "product_name", "product_code", "revision", "serial",
                    "device_type", "sw_version", "default_node_id", "tick_hz", "scope_samples",
                    "scope_channels"):
            if key not in self.device:
                raise TableError(f"[device]: missing '{key}'")
        node = self.device["default_node_id"]
        if not isinstance(node, int) or not 1 <= node <= 127:
            raise TableError("[device]: default_node_id must be 1..127")
        self.objects = {}
        for o in data.get("object", []):
            if "index" not in o or "name" not in o:
                raise TableError("[[object]]: needs index and name")
            if o["index"] in self.objects:
                raise TableError(f"[[object]] 0x{o['index']:04X}: listed twice")
            if o.get("kind", "record") not in ("record", "array"):
                raise TableError(f"[[object]] {o['name']}: kind must be record or array")
            self.objects[o["index"]] = o
        self.fn_names: set = set()
        self.params = expand_params(data.get("param", []))
        for p in self.params:
            check_param(p, self.fn_names)
        self.tpdos = self._pdos(data.get("tpdo", []), "tpdo", 0x180, 0x1800, 0x1A00, "ro")
        self.rpdos = self._pdos(data.get("rpdo", []), "rpdo", 0x200, 0x1400, 0x1600, "rw")
        self.params += self._pdo_params()
        self.emcy = self._emcy(data.get("emcy", []), data.get("emcy_extra", []))
        self._check_unique()
        self._check_objects()
        self.params.sort(key=lambda p: (p.index, p.sub))
        self.by_name = {p.name: p for p in self.params}
        self._set_signature()
        self._check_unique()
        self._check_scope()
        self._check_ranges()

    # The entry that carries the dictionary's signature (its default is computed here).
    SIGNATURE = "dictionary_signature"

    def _set_signature(self):
        """CRC-32 of what a tool on the bus relies on, entry by entry (address, name, type,
        access, unit, scale, range, allowed values, default, PDO mapping), the signature entry
        itself excepted: the EDS and the firmware built from one table carry the same value, so
        dtctune refuses an EDS of another firmware instead of misreading the drive."""
        sig = self.by_name.get(self.SIGNATURE)
        if sig is None:
            raise TableError(f"the table needs the '{self.SIGNATURE}' entry (bind const, UNSIGNED32)")
        if sig.type != "UNSIGNED32" or sig.bind != "const":
            raise TableError(f"{self.SIGNATURE}: must be an UNSIGNED32 constant")
        rows = [repr((p.index, p.sub, p.name, p.type, p.access, p.unit, p.scale, p.min, p.max, p.allowed,
                      p.default, p.pdo)) for p in self.params if p is not sig]
        sig.default = sig.raw_def = zlib.crc32("\n".join(rows).encode("utf-8"))

    def _pdos(self, raw, what, cob_base, comm_base, map_base, access):
        out = []
        names = {p.name: p for p in self.params}
        seen = set()
        for t in raw:
            num = t.get("num")
            if not isinstance(num, int) or not 1 <= num <= 4 or num in seen:
                raise TableError(f"[[{what}]]: num must be 1..4 and unique")
            seen.add(num)
            sigs = t.get("signals", [])
            bits = 0
            plist = []
            for s in sigs:
                p = names.get(s)
                if p is None:
                    raise TableError(f"[[{what}]] {num}: unknown signal '{s}'")
                if not p.pdo:
                    raise TableError(f"[[{what}]] {num}: {s} is not pdo = true")
                if p.kind in ("string", "domain"):
                    raise TableError(f"[[{what}]] {num}: {s} cannot be mapped")
                if what == "rpdo" and p.access != "rw":
                    raise TableError(f"[[{what}]] {num}: {s} is not writable")
                bits += p.size * 8
                plist.append(p)
            if not plist or bits > 64:
                raise TableError(f"[[{what}]] {num}: needs 1..64 bits of signals, has {bits}")
            out.append({"num": num, "name": t.get("name", f"{what.upper()}{num}"), "params": plist,
                        "bytes": bits // 8, "cob": cob_base + 0x100 * (num - 1),
                        "comm": comm_base + num - 1, "map": map_base + num - 1})
        return sorted(out, key=lambda x: x["num"])

    def _pdo_params(self):
        """Communication and mapping objects of the PDOs (constants)."""
        gen = []

        def mk(name, index, sub, typ, default, bind, desc):
            return Param(name=name, base=name, index=index, sub=sub, type=typ, unit="", scale=1.0,
                         resolution=1.0, min=None, max=None, allowed=None, default=default,
                         access="ro", persist=False, runtime=False, pdo=False,
                         bind=bind, ctype=None, description=desc, generated=True)

        for kind, pdos, nobit in (("tpdo", self.tpdos, 0x40000000), ("rpdo", self.rpdos, 0)):
            for t in pdos:
                n = t["num"]
                comm, mp = t["comm"], t["map"]
                self.objects.setdefault(comm, {"index": comm, "name": f"{kind}{n}_communication",
                                               "description": f"{kind.upper()} {n} communication parameters."})
                self.objects.setdefault(mp, {"index": mp, "name": f"{kind}{n}_mapping",
                                             "description": f"{kind.upper()} {n} mapping (static)."})
                gen.append(mk(f"{kind}{n}_cob_id", comm, 1, "UNSIGNED32", nobit + t["cob"], "nodeid",
                              f"COB-ID 0x{t['cob']:03X} + node id" +
                              (" (bit 30: no RTR)" if nobit else "") + "."))
                gen.append(mk(f"{kind}{n}_transmission_type", comm, 2, "UNSIGNED8",
                              0xFE if kind == "tpdo" else 0xFF, "const",
                              "0xFE: event-driven, manufacturer-specific (sent at telemetry_hz)."
                              if kind == "tpdo" else "0xFF: event-driven, device profile (applied on receipt)."))
                if kind == "tpdo":
                    gen.append(mk(f"{kind}{n}_inhibit_time", comm, 3, "UNSIGNED16", 0, "const",
                                  "Inhibit time, 100 us (none)."))
                    gen.append(mk(f"{kind}{n}_event_timer", comm, 5, "UNSIGNED16", 0, "const",
                                  "Event timer, ms (not used: the rate is telemetry_hz)."))
                for j, p in enumerate(t["params"]):
                    word = (p.index << 16) | (p.sub << 8) | (p.size * 8)
                    gen.append(mk(f"{kind}{n}_map_{j + 1}", mp, j + 1, "UNSIGNED32", word, "const",
                                  f"Maps {p.name} (0x{p.index:04X}:{p.sub}, {p.size * 8} bits)."))
        for p in gen:
            check_param(p, self.fn_names)
        return gen

    def _emcy(self, raw, extra):
        out = []
        for e in raw + extra:
            key = e.get("fault") or e.get("name")
            if not key or not NAME_RE.match(key):
                raise TableError("[[emcy]]: needs fault (a ctl_fault name) or name")
            code = e.get("code")
            if not isinstance(code, int) or not 0 < code <= 0xFFFF:
                raise TableError(f"[[emcy]] {key}: code must be 0x0001..0xFFFF")
            reg = e.get("register")
            if reg not in ERROR_REGISTER_BITS:
                raise TableError(f"[[emcy]] {key}: register must be one of {', '.join(ERROR_REGISTER_BITS)}")
            out.append({"key": key, "fault": "fault" in e, "code": code,
                        "bit": ERROR_REGISTER_BITS[reg], "register": reg,
                        "description": e.get("description", "")})
        return out

    def _check_unique(self):
        names, where = {}, {}
        for p in self.params:
            if p.name in names:
                raise TableError(f"{p.name}: name used twice")
            names[p.name] = p
            key = (p.index, p.sub)
            if key in where:
                raise TableError(f"{p.name}: 0x{p.index:04X}:{p.sub} already used by {where[key].name}")
            where[key] = p

    def _check_objects(self):
        by_index = {}
        for p in self.params:
            by_index.setdefault(p.index, []).append(p)
        self.indices = []
        for index in sorted(by_index):
            subs = by_index[index]
            if len(subs) == 1 and subs[0].sub == 0:
                self.indices.append((index, None, subs))
                continue
            given0 = [p for p in subs if p.sub == 0]
            if given0 and given0[0].bind_kind != "CO_BIND_ERRHIST":
                raise TableError(f"0x{index:04X}: subindex 0 is generated for objects with subindexes "
                                 "(only the error history 0x1003 gives its own: the count of errors)")
            obj = self.objects.get(index)
            if obj is None:
                raise TableError(f"0x{index:04X}: needs an [[object]] entry (name of the record)")
            elements = [p for p in subs if p.sub != 0]
            if obj.get("kind") == "array" and len({p.type for p in elements}) != 1:
                raise TableError(f"0x{index:04X}: an array needs one data type")
            if given0:
                if given0[0].type != "UNSIGNED8":
                    raise TableError(f"{given0[0].name}: subindex 0 is UNSIGNED8")
                self.indices.append((index, obj, given0 + sorted(elements, key=lambda p: p.sub)))
                continue
            # Subindex 0 of a record or array: the highest subindex, constant.
            sub0 = Param(name=f"{obj['name']}_highest_subindex", base=obj["name"], index=index, sub=0,
                         type="UNSIGNED8", unit="", scale=1.0, resolution=1.0, min=None, max=None,
                         allowed=None, default=max(p.sub for p in subs), access="const", persist=False,
                         runtime=False, pdo=False, bind="const", ctype=None,
                         description="Highest subindex supported.", generated=True)
            check_param(sub0, self.fn_names)
            self.params.append(sub0)
            self.indices.append((index, obj, [sub0] + sorted(subs, key=lambda p: p.sub)))
        for index in self.objects:
            if index not in by_index:
                raise TableError(f"[[object]] 0x{index:04X}: no parameter uses it")

    def _check_ranges(self):
        """range_within: the bus range of a parameter lies inside another's of the
        same unit (an unsigned type is a magnitude: both signs), so that no object
        asks for more than the parameter the drive declares as the limit."""
        for p in self.params:
            other = getattr(p, "range_within", None)
            if other is None:
                continue
            q = self.by_name.get(other) if isinstance(other, str) else None
            if q is None:
                raise TableError(f"{p.name}: range_within names no parameter ('{other}')")
            if q is p or q.unit != p.unit or p.kind not in ("uint", "sint", "real") or \
                    q.kind not in ("sint", "real"):
                raise TableError(f"{p.name}: range_within needs another signed or REAL32 parameter of the "
                                 f"same unit ({q.name} is {q.type} in '{q.unit}', {p.name} in '{p.unit}')")
            if p.min is None or q.min is None:
                raise TableError(f"{p.name}: range_within needs min and max on {p.name} and {q.name}")
            ends = [p.min, p.max] + ([-p.max] if p.kind == "uint" else [])
            if min(ends) < q.min or max(ends) > q.max:
                what = f"a magnitude up to {fmt_range(p.max)}" if p.kind == "uint" else \
                    f"{fmt_range(p.min)}..{fmt_range(p.max)}"
                raise TableError(f"{p.name}: its range ({what} {p.unit}) exceeds {q.name}'s "
                                 f"{fmt_range(q.min)}..{fmt_range(q.max)} {q.unit} (range_within)")

    def _check_scope(self):
        tel = [p for p in self.params if p.index == 0x3000 and p.sub != 0]
        self.tel = tel
        for p in tel:
            if p.bind_kind != "DRIVE_BIND_SNAP":
                raise TableError(f"{p.name}: telemetry (0x3000) must bind snap.*")
        subs = [p.sub for p in tel]
        if subs != list(range(1, len(tel) + 1)):
            raise TableError("0x3000: telemetry subindexes must be 1..N without gaps")
        for p in self.params:
            if p.base == "scope_channel" and p.max != len(tel):
                raise TableError(f"{p.name}: max must be the number of telemetry signals ({len(tel)})")


# ------------------------------------------------------------------ C output


def fmt_range(x) -> str:
    return f"{x:g}" if isinstance(x, float) else str(x)


def c_string(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def c_num(p: Param, v) -> str:
    if v is None:
        return "{.u = 0u}"
    if p.kind == "real":
        return "{.f = " + c_float(v) + "}"
    if p.kind == "sint":
        if v == -(2**31):
            return "{.i = (-2147483647 - 1)}"
        return "{.i = " + str(int(v)) + "}"
    return "{.u = " + f"0x{int(v):08X}u" + "}"


def entry_flags(p: Param) -> str:
    fl = ["CO_F_READ"]
    if p.access == "rw":
        fl.append("CO_F_WRITE")
    if p.persist:
        fl.append("CO_F_PERSIST")
    if p.runtime:
        fl.append("CO_F_RUNTIME")
    if p.pdo:
        fl.append("CO_F_PDO")
    if p.min is not None and p.kind not in ("string", "domain"):
        fl.append("CO_F_LIMITS")
    return " | ".join(fl)


def gen_header(t: Table) -> str:
    d = t.device
    fns = sorted(t.fn_names)
    lines = [
        "/* Generated by tools/params/gen_params.py from tools/params/parameters.toml. Do not edit. */",
        "/**",
        " * @file param_table.h",
        " * @brief The drive's object dictionary: entry ids, handler ids, PDO and EMCY tables.",
        " */",
        "#ifndef DTC_PARAM_TABLE_H",
        "#define DTC_PARAM_TABLE_H",
        "",
        "#include <stdint.h>",
        "",
        '#include "dtc/canopen/co_emcy.h"',
        '#include "dtc/canopen/co_od.h"',
        '#include "dtc/canopen/co_pdo.h"',
        "",
        "#ifdef __cplusplus",
        'extern "C" {',
        "#endif",
        "",
        f"#define CO_PARAM_COUNT {len(t.params)}u",
        f"#define CO_DEFAULT_NODE_ID {d['default_node_id']}u",
        f"#define CO_TICK_HZ {d['tick_hz']}u",
        f"#define CO_TEL_INDEX 0x3000u",
        f"#define CO_TEL_COUNT {len(t.tel)}u /**< telemetry signals 0x3000:1..N (scope channels) */",
        f"#define CO_SCOPE_SAMPLES {d['scope_samples']}u",
        f"#define CO_SCOPE_CHANNELS {d['scope_channels']}u",
        f"#define CO_TPDO_COUNT {len(t.tpdos)}u",
        f"#define CO_RPDO_COUNT {len(t.rpdos)}u",
        f"#define CO_EMCY_COUNT {len(t.emcy)}u",
        f"#define CO_PERSIST_BYTES {sum(4 + p.size for p in t.params if p.persist)}u"
        " /**< payload bytes of a stored parameter set (4-byte record header + value each) */",
        f"#define CO_STRING_MAX {max([len(p.default) for p in t.params if p.kind == 'string'] + [4])}u"
        " /**< longest constant string, bytes */",
        "",
        "/** Position of each entry in co_params[] (sorted by index, subindex). */",
        "typedef enum {",
    ]
    for i, p in enumerate(t.params):
        lines.append(f"    {p.ident} = {i},")
    lines += ["} co_param_id;", "", "/** Handlers of DRIVE_BIND_FN entries (drive_co.c). */",
              "typedef enum {"]
    for i, fn in enumerate(fns):
        lines.append(f"    CO_FN_{fn.upper()} = {i},")
    lines += [f"    CO_FN_COUNT = {len(fns)}", "} co_fn_id;", "",
              ]
    for i, e in enumerate(t.emcy):
        if not e["fault"]:
            lines.append(f"#define CO_EMCY_{e['key']} {i}u /**< co_emcy_table index: {e['description']} */")
    lines += ["",
              "extern const co_param co_params[CO_PARAM_COUNT];",
              "extern const co_pdo_map co_tpdo_maps[CO_TPDO_COUNT];",
              "extern const co_pdo_map co_rpdo_maps[CO_RPDO_COUNT];",
              "extern const co_emcy_entry co_emcy_table[CO_EMCY_COUNT];",
              "",
              "#ifdef __cplusplus",
              "}",
              "#endif",
              "",
              "#endif /* DTC_PARAM_TABLE_H */",
              ""]
    return "\n".join(lines)


def gen_source(t: Table) -> str:
    lines = [
        "/* Generated by tools/params/gen_params.py from tools/params/parameters.toml. Do not edit. */",
        "#include \"dtc/param_table.h\"",
        "",
        "#include <stddef.h>",
        "",
        "#include \"dtc/canopen/co_dev.h\"",
        "#include \"dtc/drive.h\"",
        "#include \"dtc/drive_co.h\"",
        "#include \"dtc/scope.h\"",
        "",
        "/* Compile-time proof that every binding names a field of the C type the table says. */",
        "#define CO_FIELD(T, path) (((T *)0)->path)",
    ]
    for p in t.params:
        if p.bind_struct is None or p.ctype_name is None:
            continue
        field = f"CO_FIELD({p.bind_struct}, {p.path})"
        ctype = CTYPES[p.ctype_name][1]
        if ctype is None:
            lines.append(f"_Static_assert(sizeof {field} == 1 || sizeof {field} == 2 || sizeof {field} == 4, "
                         f"\"{p.name}: enum size\");")
        else:
            lines.append(f"_Static_assert(_Generic({field}, {ctype}: 1, default: 0), \"{p.name}: {p.path} is not {ctype}\");")
    lines.append("")
    for p in t.params:
        if p.allowed:
            vals = ", ".join(f"{a}u" for a in p.allowed)
            lines.append(f"static const uint32_t allowed_{p.name}[{len(p.allowed)}] = {{{vals}}};")
    lines += ["", "const co_param co_params[CO_PARAM_COUNT] = {"]
    for p in t.params:
        if p.kind in ("string", "domain"):
            ckind, csize = "CO_CK_BYTES", "0u"
        else:
            ckind = CTYPES[p.ctype_name][0]
            if p.bind_struct is not None:
                csize = f"(uint8_t)sizeof CO_FIELD({p.bind_struct}, {p.path})"
            else:
                csize = str(p.size) + "u"
        if p.bind_kind == "DRIVE_BIND_FN":
            offset = f"CO_FN_{p.path.upper()}"
        elif p.bind_struct is not None:
            offset = f"(uint16_t)offsetof({p.bind_struct}, {p.path})"
        else:
            offset = "0u"
        k = p.scale / p.resolution
        allowed = f"allowed_{p.name}" if p.allowed else "NULL"
        nallowed = len(p.allowed) if p.allowed else 0
        sval = c_string(p.default) if p.kind == "string" else "NULL"
        dflt = None if p.kind in ("string", "domain") else p.raw_def
        lines.append(
            f"    [{p.ident}] = {{{c_string(p.name)}, 0x{p.index:04X}u, {p.sub}u, 0x{p.code:02X}u, "
            f"{entry_flags(p)}, {p.bind_kind}, {ckind}, {csize}, {offset}, {c_float(k)}, "
            f"{c_num(p, getattr(p, 'raw_min', None))}, {c_num(p, getattr(p, 'raw_max', None))}, "
            f"{c_num(p, dflt)}, {allowed}, {nallowed}u, {sval}, {c_float(getattr(p, 'max_step', 0.0) or 0.0)}}},")
    lines += ["};", ""]
    for name, pdos in (("co_tpdo_maps", t.tpdos), ("co_rpdo_maps", t.rpdos)):
        lines.append(f"const co_pdo_map {name}[{'CO_TPDO_COUNT' if 'tpdo' in name else 'CO_RPDO_COUNT'}] = {{")
        for m in pdos:
            ids = ", ".join(p.ident for p in m["params"])
            lines.append(f"    {{0x{m['cob']:03X}u, {len(m['params'])}u, {m['bytes']}u, {{{ids}}}}},")
        lines += ["};", ""]
    lines.append("const co_emcy_entry co_emcy_table[CO_EMCY_COUNT] = {")
    for e in t.emcy:
        bit = f"(uint32_t){e['key']}" if e["fault"] else "0u"
        lines.append(f"    {{{bit}, 0x{e['code']:04X}u, {e['bit']}u}}, /* {e['key']} */")
    lines += ["};", ""]
    return "\n".join(lines)


# ----------------------------------------------------------------- EDS output


def eds_value(p: Param) -> str:
    if p.kind == "string":
        return p.default
    if p.kind == "real":
        return fmt_num(p.raw_def, "real")
    if p.bind_kind == "CO_BIND_NODEID":
        return f"$NODEID+0x{int(p.default):X}"
    if p.type == "UNSIGNED32" or p.index < 0x2000:
        return f"0x{int(p.default):X}" if p.type.startswith("UNSIGNED") else str(int(p.default))
    return str(int(p.default))


def eds_access(p: Param) -> str:
    if p.access == "const":
        return "const"
    if p.access == "ro":
        return "ro"
    return "rw"


def eds_var(section: str, p: Param, name: str) -> list[str]:
    out = [f"[{section}]", f"ParameterName={name}", "ObjectType=0x7", f"DataType=0x{p.code:04X}",
           f"AccessType={eds_access(p)}"]
    if p.kind != "domain":
        out.append(f"DefaultValue={eds_value(p)}")
    if p.min is not None and p.kind not in ("string", "domain"):
        out.append(f"LowLimit={fmt_num(p.raw_min, p.kind)}")
        out.append(f"HighLimit={fmt_num(p.raw_max, p.kind)}")
    out.append(f"PDOMapping={1 if p.pdo else 0}")
    desc = p.description.replace("\n", " ")
    out.append(f"Description={desc}")
    if p.unit:
        out.append(f"Unit={p.unit}")
    if p.kind not in ("string", "domain") and p.resolution != 1.0 and p.kind != "real":
        out.append(f"Factor={p.resolution!r}")
    out.append("")
    return out


def eds_time(epoch: float) -> tuple:
    """CiA 306 FileInfo date and time of a UTC instant: ('mm-dd-yyyy', 'hh:mm(AM|PM)')."""
    import time as _time
    tm = _time.gmtime(epoch)
    hour12 = tm.tm_hour % 12 or 12
    return (f"{tm.tm_mon:02d}-{tm.tm_mday:02d}-{tm.tm_year:04d}",
            f"{hour12:02d}:{tm.tm_min:02d}{'AM' if tm.tm_hour < 12 else 'PM'}")


def eds_created(t: Table) -> float:
    """[device] eds_created ('YYYY-MM-DD HH:MM', UTC) as a UNIX time."""
    import calendar
    import time as _time
    v = t.device.get("eds_created")
    try:
        return float(calendar.timegm(_time.strptime(str(v), "%Y-%m-%d %H:%M")))
    except ValueError:
        raise TableError(f"[device]: eds_created must be 'YYYY-MM-DD HH:MM' (UTC), got {v!r}") from None


def gen_eds(t: Table, modified: float = 0.0) -> str:
    """The EDS; FileInfo's creation date from the table, its modification date @p modified
    (UNIX time: SOURCE_DATE_EPOCH, else the table file's modification time)."""
    d = t.device
    c_date, c_time = eds_time(eds_created(t))
    m_date, m_time = eds_time(max(modified, eds_created(t)))
    mandatory = [0x1000, 0x1001, 0x1018]
    groups = {"MandatoryObjects": [], "OptionalObjects": [], "ManufacturerObjects": []}
    for index, _, _ in t.indices:
        if index in mandatory:
            groups["MandatoryObjects"].append(index)
        elif 0x2000 <= index <= 0x5FFF:
            groups["ManufacturerObjects"].append(index)
        else:
            groups["OptionalObjects"].append(index)
    out = [
        "; Generated by tools/params/gen_params.py from tools/params/parameters.toml. Do not edit.",
        "[FileInfo]",
        "FileName=drive.eds",
        "FileVersion=1",
        "FileRevision=0",
        "EDSVersion=4.0",
        f"Description={d['product_name']}",
        f"CreationTime={c_time}",
        f"CreationDate={c_date}",
        "CreatedBy=gen_params.py",
        f"ModificationTime={m_time}",
        f"ModificationDate={m_date}",
        "ModifiedBy=gen_params.py",
        "",
        "[DeviceInfo]",
        f"VendorName={d['vendor_name']}",
        f"VendorNumber=0x{d['vendor_id']:08X}",
        f"ProductName={d['product_name']}",
        f"ProductNumber=0x{d['product_code']:08X}",
        f"RevisionNumber=0x{d['revision']:08X}",
        "OrderCode=",
        "BaudRate_10=0", "BaudRate_20=0", "BaudRate_50=0", "BaudRate_125=1", "BaudRate_250=1",
        "BaudRate_500=1", "BaudRate_800=0", "BaudRate_1000=1",
        "SimpleBootUpMaster=0", "SimpleBootUpSlave=1", "Granularity=8",
        "DynamicChannelsSupported=0", "CompactPDO=0", "GroupMessaging=0",
        f"NrOfRXPDO={len(t.rpdos)}", f"NrOfTXPDO={len(t.tpdos)}", "LSS_Supported=0",
        "",
        "[DummyUsage]",
    ]
    out += [f"Dummy000{i}=0" for i in range(1, 8)]
    out += ["", "[Comments]", "Lines=2",
            "Line1=Parameter table: tools/params/parameters.toml (single source of truth).",
            "Line2=Telemetry TPDO scaling: telemetry.dbc; reference: docs/parameters.md.", ""]
    for g, idx in groups.items():
        out.append(f"[{g}]")
        out.append(f"SupportedObjects={len(idx)}")
        for i, index in enumerate(idx):
            out.append(f"{i + 1}=0x{index:04X}")
        out.append("")
    for index, obj, subs in t.indices:
        if obj is None:
            out += eds_var(f"{index:04X}", subs[0], subs[0].name)
            continue
        kind = obj.get("kind", "record")
        out += [f"[{index:04X}]", f"ParameterName={obj['name']}",
                f"ObjectType={'0x8' if kind == 'array' else '0x9'}", f"SubNumber={len(subs)}",
                f"Description={obj.get('description', '')}", ""]
        for p in subs:
            name = "highest_subindex" if p.sub == 0 and p.generated else p.name
            out += eds_var(f"{index:04X}sub{p.sub:X}", p, name)
    return "\n".join(out)


# ----------------------------------------------------------------- DBC output


def dbc_number(x: float) -> str:
    s = repr(float(x))
    if s.endswith(".0"):
        s = s[:-2]
    return s


def gen_dbc(t: Table) -> str:
    node = t.device["default_node_id"]
    out = [
        'VERSION ""',
        "",
        "NS_ :",
        "    CM_",
        "    BA_DEF_",
        "    BA_",
        "    VAL_",
        "",
        "BS_:",
        "",
        "BU_: DRIVE HOST",
        "",
    ]
    comments = [f'CM_ "Telemetry TPDOs of the drive at node id {node} (COB-ID = base + node id). '
                f'Generated by tools/params/gen_params.py from tools/params/parameters.toml.";']
    for m in t.tpdos:
        cob = m["cob"] + node
        out.append(f"BO_ {cob} {m['name']}: {m['bytes']} DRIVE")
        bit = 0
        for p in m["params"]:
            nbits = p.size * 8
            signed = p.kind == "sint"
            lo, hi = TYPES[p.type][3], TYPES[p.type][4]
            fac = p.resolution
            sig = p.name[4:] if p.name.startswith("pdo_") else p.name
            out.append(f' SG_ {sig} : {bit}|{nbits}@1{"-" if signed else "+"} ({dbc_number(fac)},0) '
                       f'[{dbc_number(lo * fac)}|{dbc_number(hi * fac)}] "{p.unit}" HOST')
            comments.append(f'CM_ SG_ {cob} {sig} "{p.description}";')
            bit += nbits
        out.append("")
        comments.append(f'CM_ BO_ {cob} "TPDO{m["num"]} (0x{m["cob"]:03X} + node id), sent at telemetry_hz '
                        f'in NMT operational.";')
    out += comments
    out.append("")
    return "\n".join(out)


# ------------------------------------------------------------ Markdown output


def md_escape(s: str) -> str:
    return s.replace("|", "\\|")


def md_value(p: Param, v) -> str:
    if v is None:
        return ""
    if p.kind == "string":
        return f'"{v}"'
    if p.kind == "real":
        return fmt_num(v, "real")
    if p.bind_kind == "CO_BIND_NODEID":
        return f"0x{int(v):X} + node id"
    if p.index < 0x2000 and p.type == "UNSIGNED32":
        return f"0x{int(v):X}"
    return str(int(v))


def gen_md(t: Table) -> str:
    d = t.device
    out = [
        "# Drive parameters and CANopen objects",
        "",
        "<!-- Generated by tools/params/gen_params.py from tools/params/parameters.toml; do not edit.",
        "     A unit test checks that this checked-in copy equals the generated one. -->",
        "",
        f"{d['product_name']}, CANopen (CiA 301) device, default node id {d['default_node_id']}.",
        "Every value below comes from one table, `tools/params/parameters.toml`, which also generates",
        "the firmware's object dictionary, `drive.eds` and `telemetry.dbc` (in the build directory).",
        "",
        "Columns: **Access** `rw` read/write, `ro` read only, `const` constant; **P** persists",
        "(stored by writing \"save\" to 0x1010:1, loaded at boot); **R** may change while the drive",
        "runs (a write to a parameter without R while the drive runs is refused with 0x08000022).",
        "Values are in the unit shown (the firmware works in SI: rad/s, N m, Wb; speeds on the bus",
        "are rpm = rad/s x 60 / 2 pi). Writes outside Min..Max are refused with 0x06090032 (too low)",
        "or 0x06090031 (too high) and change nothing.",
        "",
        "## Device behaviour",
        "",
        "- **NMT** (COB-ID 0x000, 2 bytes: command, node id or 0 for all): 0x01 start (operational),",
        "  0x02 stop, 0x80 pre-operational, 0x81 reset node (stops the drive, reloads the stored",
        "  parameters, boots again), 0x82 reset communication (applies node_id and bitrate_kbps).",
        "  Boot-up message 0x700 + id with data 0x00, then pre-operational (or operational with",
        "  nmt_autostart = 1). Heartbeat 0x700 + id every heartbeat_ms: 0x04 stopped, 0x05",
        "  operational, 0x7F pre-operational.",
        "- **SDO server** (requests 0x600 + id, responses 0x580 + id): expedited and segmented",
        "  upload and download, one transfer at a time; a new initiate request replaces an",
        "  unfinished transfer; a segmented transfer idle for more than 1000 ms is aborted with",
        "  0x05040000. Frames with a length other than 8 and remote frames are ignored. Available in",
        "  pre-operational and operational.",
        "- **TPDOs** (operational only) carry the telemetry at telemetry_hz, all from one snapshot;",
        "  **RPDO 1** (operational only) sets target_velocity then controlword; a shorter RPDO is",
        "  ignored and reported with EMCY 0x8210.",
        "- **EMCY** (0x80 + id, not in stopped): one message per newly latched fault, 0x0000 when",
        "  all are gone. Bytes: error code (2, little-endian), error register (1), fault bits",
        "  (4, little-endian), 0.",
        "- **Persistence**: two NVM slots with a sequence number and CRC-32; a save writes the",
        "  older slot, so a power loss during a save leaves the previous set loadable; the newest",
        "  valid slot wins at boot; with both slots corrupt the drive boots with defaults,",
        "  persist_status = 3 and EMCY 0x6300.",
        "",
        "### SDO abort codes",
        "",
        "| Code | Meaning |",
        "|---|---|",
        "| 0x05030000 | toggle bit not alternated |",
        "| 0x05040000 | SDO protocol timed out (segmented transfer idle > 1000 ms) |",
        "| 0x05040001 | command specifier not valid or unknown (also block transfers, unexpected segments) |",
        "| 0x06010002 | attempt to write a read-only object |",
        "| 0x06020000 | object does not exist |",
        "| 0x06040043 | general parameter incompatibility (e.g. width 0 for a node in use) |",
        "| 0x06070010 | data type does not match, length of service parameter does not match |",
        "| 0x06090011 | subindex does not exist |",
        "| 0x06090030 | invalid value (NaN, infinity, not one of the allowed values) |",
        "| 0x06090031 | value too high |",
        "| 0x06090032 | value too low |",
        "| 0x08000020 | data cannot be stored (wrong signature for 0x1010/0x1011, NVM failure) |",
        "| 0x08000022 | refused in the present device state (parameter not changeable while running) |",
        "",
        "### Emergency codes",
        "",
        "| Fault | EMCY code | Error register bit | Meaning |",
        "|---|---|---|---|",
    ]
    for e in t.emcy:
        out.append(f"| {e['key']} | 0x{e['code']:04X} | {e['bit']} ({e['register']}) | {md_escape(e['description'])} |")
    out += ["", "### Telemetry PDOs", "",
            f"Sent in operational state at telemetry_hz (at most the {d['tick_hz']} Hz control tick). "
            "Physical value = raw x resolution.", "",
            "| PDO | COB-ID | Byte | Signal | Type | Resolution | Unit | Source |",
            "|---|---|---|---|---|---|---|---|"]
    for m in t.tpdos:
        byte = 0
        for p in m["params"]:
            out.append(f"| TPDO{m['num']} | 0x{m['cob']:03X} + id | {byte} | {p.name} | {p.type} | "
                       f"{dbc_number(p.resolution)} | {p.unit} | 0x{p.index:04X}:{p.sub} |")
            byte += p.size
    for m in t.rpdos:
        byte = 0
        for p in m["params"]:
            out.append(f"| RPDO{m['num']} | 0x{m['cob']:03X} + id | {byte} | {p.name} | {p.type} | "
                       f"{dbc_number(p.resolution)} | {p.unit} | 0x{p.index:04X}:{p.sub} |")
            byte += p.size
    out += ["", "### Scope", "",
            f"Set the channels (telemetry subindexes of 0x3000), trigger, pretrigger and decimation, write 1",
            f"to scope_command to arm, wait for scope_state = 3, then upload scope_data (0x2601) with a",
            f"segmented SDO upload: {d['scope_samples']} REAL32 samples per enabled channel, channel after channel,",
            f"in the units of the telemetry signal, oldest first; sample number scope_pretrigger is the trigger",
            f"(tick scope_trigger_tick).", ""]
    out += ["## Objects", ""]
    for index, obj, subs in t.indices:
        if obj is None:
            title = f"0x{index:04X} {subs[0].name}"
        else:
            title = f"0x{index:04X} {obj['name']}"
        out.append(f"### {title}")
        out.append("")
        if obj is not None and obj.get("description"):
            out += [md_escape(obj["description"]), ""]
        out += ["| Sub | Name | Type | Unit | Min | Max | Default | Access | P | R | Description |",
                "|---|---|---|---|---|---|---|---|---|---|---|"]
        for p in subs:
            if p.sub == 0 and obj is not None and p.generated:
                continue
            lo = md_value(p, p.raw_min) if p.kind not in ("string", "domain") and p.min is not None else ""
            hi = md_value(p, p.raw_max) if p.kind not in ("string", "domain") and p.max is not None else ""
            if p.allowed:
                lo, hi = lo + " (one of " + ", ".join(str(a) for a in p.allowed) + ")", hi
            dv = md_value(p, p.default if p.kind == "string" else getattr(p, "raw_def", None))
            unit = p.unit
            if p.kind not in ("string", "domain", "real") and p.resolution != 1.0:
                unit = f"{dbc_number(p.resolution)} {p.unit}"
            out.append(f"| {p.sub} | {p.name} | {p.type} | {md_escape(unit)} | {lo} | {hi} | {dv} | {p.access} | "
                       f"{'x' if p.persist else ''} | {'x' if p.runtime else ''} | {md_escape(p.description)} |")
        out.append("")
    return "\n".join(out)


# ----------------------------------------------------------------------- main


def write_output(path: str, text: str) -> None:
    """Write atomically (a reader never sees half a file). Always written, so the
    outputs are newer than the table and the build tool does not run us again."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
        fh.write(text)
    os.replace(tmp, path)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--table", required=True, help="parameters.toml")
    ap.add_argument("--c-header")
    ap.add_argument("--c-source")
    ap.add_argument("--eds")
    ap.add_argument("--dbc")
    ap.add_argument("--md")
    ap.add_argument("--check-md", help="exit 1 unless this file equals the generated reference")
    ap.add_argument("--check-eds", help="exit 1 unless this file equals the generated EDS (dates aside)")
    args = ap.parse_args(argv)
    try:
        table = Table(load_table(args.table))
        eds_created(table)
    except TableError as e:
        print(f"{os.path.basename(args.table)}: {e}", file=sys.stderr)
        return 2
    sde = os.environ.get("SOURCE_DATE_EPOCH", "")
    modified = float(sde) if sde.isdigit() else os.stat(args.table).st_mtime
    outputs = [(args.c_header, gen_header), (args.c_source, gen_source),
               (args.eds, lambda t: gen_eds(t, modified)),
               (args.dbc, gen_dbc), (args.md, gen_md)]
    texts = [(path, fn(table)) for path, fn in outputs if path]
    for path, text in texts:
        write_output(path, text)
    def undated(text):  # an EDS's modification date follows the table file's time, not its content
        return "\n".join(l for l in text.splitlines() if not l.startswith(("ModificationTime=", "ModificationDate=")))

    checks = [(args.check_md, "--md", gen_md(table), lambda t: t),
              (args.check_eds, "--eds", gen_eds(table, modified), undated)]
    for path, option, expected, normal in checks:
        if not path:
            continue
        try:
            with open(path, encoding="utf-8") as fh:
                current = fh.read()
        except OSError as e:
            print(f"{path}: {e.strerror}", file=sys.stderr)
            return 1
        if normal(current) != normal(expected):
            print(f"{path} is out of date: regenerate it with tools/params/gen_params.py "
                  f"--table {args.table} {option} {path}", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
