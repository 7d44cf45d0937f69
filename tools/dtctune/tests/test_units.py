"""Pieces of dtctune without a bus: abort-code wording, value parsing and range checks, PDO decoding."""
import struct

import pytest

from dtctune import abort_codes
from dtctune.errors import DtctuneError
from dtctune.od import Dictionary
from dtctune.telemetry import read_layout, rows

from conftest import EDS

# The wording the drive's users see for the codes the drive sends (CiA 301 meanings).
@pytest.mark.parametrize("code,words", [
    (0x06090031, "value too high"),
    (0x06090032, "value too low"),
    (0x06010002, "read-only"),
    (0x06020000, "no such object"),
    (0x06090011, "no such sub-index"),
    (0x06070010, "wrong data length"),
    (0x08000022, "present state"),
    (0x05030000, "toggle bit"),
    (0x05040000, "timed out"),
    (0x05040001, "unknown or invalid SDO command"),
    (0x08000020, "cannot store"),
    (0x06090030, "value not allowed"),
])
def test_abort_wording(code, words):
    text = abort_codes.describe(code)
    assert words in text
    assert "0x%08X" % code in text


def test_unknown_abort_code_shown_by_number():
    assert abort_codes.describe(0x12345678) == "abort code 0x12345678 (not a CiA 301 code)"


@pytest.fixture(scope="module")
def dic():
    return Dictionary(EDS, 1)


def test_parse_and_check(dic):
    p = dic.lookup("SPEED.REF_RPM")  # names are case-insensitive
    assert p.parse(" 1500.25 ") == pytest.approx(1500.25)
    p.check(p.parse("3000"))
    with pytest.raises(DtctuneError, match="outside the range"):
        p.check(p.parse("3000.001"))
    # a value that rounds to the limit in single precision is what the drive sees: accepted
    p.check(3000.00001)


def test_integer_types(dic):
    p = dic.lookup("rbfn.n_hidden")
    assert p.parse("0x9") == 9
    with pytest.raises(DtctuneError, match="outside"):
        p.check(p.parse("10"))
    with pytest.raises(DtctuneError, match="outside"):
        p.check(p.parse("0"))


def test_factor_scaled_value(dic):
    p = dic.lookup("tel.vc_diff_dV")
    assert p.factor == pytest.approx(0.1)
    assert p.to_raw(-3.7) == -37
    assert p.format(-37) == "-3.7"
    with pytest.raises(DtctuneError, match="multiple of the step"):
        p.to_raw(0.05)


def test_lookup_by_address_and_missing(dic):
    assert dic.lookup("0x2100:2").name == "rbfn.n_hidden"
    with pytest.raises(DtctuneError, match="no object 0x2999:0"):
        dic.lookup("0x2999:0")


def test_layout_from_eds_and_row_grouping(dic):
    tpdos = read_layout(dic, None)
    assert [(t.number, t.cob_id) for t in tpdos] == [(1, 0x181), (2, 0x281)]
    assert [s.name for s in tpdos[1].signals] == ["tel.vc_diff_dV", "tel.tick"]
    frames = [
        (10.000, 0x181, struct.pack("<ff", 1.0, 2.0)),
        (10.0001, 0x281, struct.pack("<hI", 5, 7)),
        (10.001, 0x181, struct.pack("<ff", 3.0, 4.0)),
        # TPDO2 of this period lost
        (10.002, 0x181, struct.pack("<ff", 5.0, 6.0)),
        (10.0021, 0x281, struct.pack("<hI", -5, 9)),
    ]
    got = list(rows(frames, tpdos))
    assert [t for t, _ in got] == [10.000, 10.001, 10.002]
    assert got[0][1] == {"tel.speed_est_rpm": 1.0, "tel.te_ref_Nm": 2.0, "tel.vc_diff_dV": 0.5, "tel.tick": 7}
    assert "tel.tick" not in got[1][1]  # lost frame: empty, not repeated
    assert got[2][1]["tel.vc_diff_dV"] == pytest.approx(-0.5)


def test_rows_start_at_a_whole_cycle(dic):
    tpdos = read_layout(dic, None)
    frames = [
        (9.9995, 0x281, struct.pack("<hI", 1, 6)),   # tail of a cycle that began before the recording
        (10.000, 0x181, struct.pack("<ff", 1.0, 2.0)),
        (10.0001, 0x281, struct.pack("<hI", 5, 7)),
    ]
    got = list(rows(frames, tpdos))
    assert len(got) == 1 and got[0][0] == 10.000 and got[0][1]["tel.tick"] == 7


def test_scope_channels_and_decoding(dic):
    from dtctune import scope
    chans = scope.resolve_channels(dic, "tel.speed_est_rpm, 2")
    assert [(c.index, c.subindex) for c in chans] == [(0x3000, 1), (0x3000, 2)]
    with pytest.raises(DtctuneError, match="at most 4"):
        scope.resolve_channels(dic, "1,2,3,4,1")
    with pytest.raises(DtctuneError, match="not a telemetry signal"):
        scope.resolve_channels(dic, "speed.ref_rpm")
    samples = 8
    data = struct.pack("<16f", *[float(k) for k in range(8)], *[-float(k) for k in range(8)])
    tr = scope.decode(data, 2, samples)
    assert tr[0] == [float(k) for k in range(8)] and tr[1][7] == -7.0
    with pytest.raises(DtctuneError, match="expected 64"):
        scope.decode(data[:-4], 2, samples)


# The drive's naming (as in tools/params/parameters.toml): a parameter speed_ref_rpm (the set
# point), telemetry signals tel_*_UNIT at 0x3000, and their TPDO copies pdo_* at 0x3100.
DRIVE_LIKE_EDS = """
[2000]
ParameterName=speed
ObjectType=0x9
SubNumber=2
[2000sub0]
ParameterName=highest_subindex
DataType=0x0005
AccessType=const
DefaultValue=1
[2000sub1]
ParameterName=speed_ref_rpm
DataType=0x0008
AccessType=rw
DefaultValue=0.0
[3000]
ParameterName=telemetry
ObjectType=0x9
SubNumber=7
[3000sub0]
ParameterName=highest_subindex
DataType=0x0005
AccessType=const
DefaultValue=6
[3000sub1]
ParameterName=tel_speed_ref_rpm
DataType=0x0008
AccessType=ro
[3000sub2]
ParameterName=tel_speed_est_rpm
DataType=0x0008
AccessType=ro
[3000sub3]
ParameterName=tel_te_ref_Nm
DataType=0x0008
AccessType=ro
[3000sub4]
ParameterName=tel_psi_s_Wb
DataType=0x0008
AccessType=ro
[3000sub5]
ParameterName=tel_psi_ref_Wb
DataType=0x0008
AccessType=ro
[3000sub6]
ParameterName=tel_ia_A
DataType=0x0008
AccessType=ro
[3100]
ParameterName=telemetry_pdo
ObjectType=0x9
SubNumber=4
[3100sub0]
ParameterName=highest_subindex
DataType=0x0005
AccessType=const
DefaultValue=3
[3100sub1]
ParameterName=pdo_speed_ref
DataType=0x0003
AccessType=ro
[3100sub2]
ParameterName=pdo_psi_s
DataType=0x0003
AccessType=ro
[3100sub3]
ParameterName=pdo_seq
DataType=0x0006
AccessType=ro
"""


@pytest.fixture
def drive_like(tmp_path):
    p = tmp_path / "drive_like.eds"
    p.write_text(DRIVE_LIKE_EDS)
    return Dictionary(p, 1)


@pytest.mark.parametrize("spec,subs", [
    # README: the parameter's name resolves to its telemetry signal, not to the parameter
    ("speed_ref_rpm,speed_est_rpm,te_ref_Nm,ia_A", [1, 2, 3, 6]),
    ("tel_speed_ref_rpm,TEL_SPEED_EST_RPM", [1, 2]),
    # the names monitor and record show (TPDO signals)
    ("pdo_speed_ref,pdo_psi_s", [1, 4]),
    ("speed_ref,psi_s,psi_ref", [1, 4, 5]),
    ("6,1", [6, 1]),
])
def test_scope_channel_names(drive_like, spec, subs):
    from dtctune import scope
    assert [(c.index, c.subindex) for c in scope.resolve_channels(drive_like, spec)] == [(0x3000, s) for s in subs]


@pytest.mark.parametrize("name,words", [
    ("pdo_seq", "'pdo_seq' is a TPDO signal without a scope channel"),
    ("bogus", "'bogus' is not a telemetry signal"),
    ("psi", "'psi' is not a telemetry signal"),    # ambiguous: psi_s_Wb or psi_ref_Wb
    ("9", "'9' is not a telemetry signal"),
])
def test_scope_bad_channel_lists_the_valid_ones(drive_like, name, words):
    from dtctune import scope
    with pytest.raises(DtctuneError) as e:
        scope.resolve_channels(drive_like, name)
    msg = str(e.value)
    assert words in msg
    assert "speed_ref_rpm, speed_est_rpm, te_ref_Nm, psi_s_Wb, psi_ref_Wb, ia_A" in msg


def test_eds_read_once_without_canopen(tmp_path):
    """The EDS reader needs neither canopen nor python-can (start-up), and reads each file once."""
    import subprocess, sys
    code = ("import sys, builtins\n"
            "opened = []\n"
            "real = builtins.open\n"
            "from dtctune.od import Dictionary\n"
            "def op(f, *a, **k):\n"
            "    if str(f).endswith('.eds'): opened.append(str(f))\n"
            "    return real(f, *a, **k)\n"
            "builtins.open = op\n"
            "d = Dictionary(sys.argv[1], 1)\n"
            "assert d.lookup('rbfn.gamma_w').var.max == 1000.0, d.lookup('rbfn.gamma_w').var\n"
            "print(len(opened), 'can' in sys.modules, 'canopen' in sys.modules)\n")
    r = subprocess.run([sys.executable, "-c", code, str(EDS)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["1", "False", "False"]


def test_real32_limits_and_nodeid_defaults(dic):
    # REAL32 limits written as floats (canopen's parser skipped them) and $NODEID defaults
    assert dic.lookup("speed.ref_rpm").raw_limits() == (-3000.0, 3000.0)
    assert dic.default(0x1800, 1) & 0x7FF == 0x181
