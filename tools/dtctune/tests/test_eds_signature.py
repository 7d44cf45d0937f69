"""Which EDS dtctune uses, and whether it is the drive's: with no --eds, no $DTCTUNE_EDS and no
build tree the EDS packaged with dtctune (data/drive.eds); the drive's dictionary signature
(0x2510:8) must equal the EDS's, else one error line and nothing is sent."""
import struct

import pytest

from dtctune import od
from conftest import FakeDrive

PACKAGED = od.PACKAGED_EDS
SIG = (0x2510, 8)


@pytest.fixture
def no_build_tree(tmp_path, monkeypatch):
    """As on a PC with only the tool installed: not in a checkout, no build tree, no variable."""
    monkeypatch.setattr(od, "repo_root", lambda: None)
    monkeypatch.delenv("DTCTUNE_EDS", raising=False)
    monkeypatch.chdir(tmp_path)


def eds_signature(path):
    sec = None
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            if line.startswith("["):
                sec = line
            elif sec == "[2510sub8]" and line.startswith("DefaultValue="):
                return int(line.split("=", 1)[1], 0)
    raise AssertionError("no dictionary signature in %s" % path)


def test_the_packaged_eds_is_found_without_a_build_tree_and_fits_its_drive(channel, run, no_build_tree):
    assert od.find_eds(None) == PACKAGED
    drive = FakeDrive(channel, eds=PACKAGED)  # a drive built from the same table
    try:
        status, out, err = run("get", "rbfn_gamma_w", eds=None)
    finally:
        drive.close()
    assert status == 0, err
    assert out.strip() == "rbfn_gamma_w = 4000.0", out


def test_an_eds_of_another_firmware_is_refused_before_anything_is_written(channel, run, no_build_tree):
    drive = FakeDrive(channel, eds=PACKAGED)
    drive.node.set_data(*SIG, struct.pack("<L", eds_signature(PACKAGED) ^ 0x1))  # one bit: another table
    drive.writes.clear()  # that local write is not the tool's
    try:
        status, out, err = run("set", "rbfn_gamma_w", "4100", eds=None)
    finally:
        drive.close()
    assert status == 2
    lines = [l for l in err.splitlines() if l.strip()]
    assert len(lines) == 1 and "is not this drive's" in lines[0] and PACKAGED in lines[0], err
    assert drive.writes == []


def test_a_drive_without_the_signature_needs_the_eds_named(channel, run, tmp_path, no_build_tree):
    """An older firmware (no 0x2510:8): the packaged EDS is not assumed to fit; an EDS the user
    names with --eds is taken as given."""
    old_eds = tmp_path / "old.eds"
    text = open(PACKAGED, encoding="utf-8").read()
    head, rest = text.split("[2510sub8]", 1)
    old_eds.write_text(head + "[2510sub8_gone]" + rest, encoding="utf-8")  # the drive lacks the entry
    drive = FakeDrive(channel, eds=old_eds)
    try:
        status, _, err = run("get", "rbfn_gamma_w", eds=None)
        assert status == 2 and "no dictionary signature" in err, err
        status, out, err = run("get", "rbfn_gamma_w", eds=PACKAGED)
        assert status == 0 and out.strip() == "rbfn_gamma_w = 4000.0", err
    finally:
        drive.close()
