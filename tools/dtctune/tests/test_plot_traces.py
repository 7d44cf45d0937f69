"""tools/plot_traces.py on synthetic dtc-sim traces: a PNG for good input, one error line for bad."""
import importlib.util
import math
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "plot_traces.py"
spec = importlib.util.spec_from_file_location("plot_traces", SCRIPT)
plot_traces = importlib.util.module_from_spec(spec)
spec.loader.exec_module(plot_traces)

HEADER = ("t_s,omega_m_rad_s,speed_rpm,te_nm,ia_a,ib_a,ic_a,vc1_v,vc2_v,t_load_nm,ref_cmd_rpm,"
          "speed_ref_rpm,speed_est_rpm,speed_err_true_rpm,te_ref_nm,te_est_nm,psi_s_wb,psi_ref_wb,"
          "eps_hat,eps_true,w_norm,zeta_bar,rs_est_ohm,vector,duty0,state,faults")


def synthetic(path: Path, recovery_s: float, with_eps: bool) -> None:
    """A CASE2-like run: 500 rpm, at 2.5 s a dip that recovers with time constant recovery_s."""
    lines = [HEADER]
    for k in range(0, 4000):
        t = k * 1e-3
        dip = 0.0 if t < 2.5 else 15.0 * math.exp(-(t - 2.5) / recovery_s) * min(1.0, (t - 2.5) / 0.02)
        ref = min(500.0, 500.0 * t / 0.5)
        spd = ref - dip
        load = 8.0 if t >= 2.5 else 0.0
        eps_true = -180.0 if t >= 2.5 else 0.0
        eps_hat = eps_true * (1 - math.exp(-(t - 2.5) / 0.1)) if (with_eps and t >= 2.5) else 0.0
        ia = 10 * math.sin(2 * math.pi * 17 * t)
        lines.append(",".join(str(v) for v in [
            t, spd * math.pi / 30, spd, load, ia, 0, 0, 155.5, 155.5, load, ref, ref, spd + 0.5, ref - spd,
            load + 1.0, load, 0.45, 0.45, eps_hat, eps_true, 0.1, 0.2, 0.288, 3, 1.0, 2, 0]))
    path.write_text("\n".join(lines) + "\n")


def test_fig6_png(tmp_path):
    ip, rbfn, out = tmp_path / "ip.csv", tmp_path / "rbfn.csv", tmp_path / "fig.png"
    synthetic(ip, 0.5, False)
    synthetic(rbfn, 0.07, True)
    assert plot_traces.main(["--ip", str(ip), "--rbfn", str(rbfn), "--out", str(out)]) == 0
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    from PIL import Image
    with Image.open(out) as im:
        w, h = im.size
    assert w > 1.5 * 0.9 * h / 5 * 2  # two columns, five rows: wider than two single panels
    assert h > w * 0.8


def test_fig5_three_panels(tmp_path):
    ip, out = tmp_path / "ip.csv", tmp_path / "fig5.png"
    synthetic(ip, 0.5, False)
    assert plot_traces.main(["--ip", str(ip), "--panels", "speed,current,torque", "--out", str(out)]) == 0
    assert out.stat().st_size > 1000


def test_missing_column_is_one_error_line(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("t_s,speed_rpm\n0,1\n")
    assert plot_traces.main(["--ip", str(bad), "--out", str(tmp_path / "x.png")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "needs column speed_err_true_rpm" in err[0]
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("content,words", [("", "empty file"), ("t_s,speed_rpm\n0,abc\n", "not a number"),
                                           ("a,b\n1,2\n", "no t_s column")])
def test_bad_files(tmp_path, capsys, content, words):
    bad = tmp_path / "bad.csv"
    bad.write_text(content)
    assert plot_traces.main(["--rbfn", str(bad), "--out", str(tmp_path / "x.png")]) == 2
    assert words in capsys.readouterr().err


def test_missing_file(tmp_path, capsys):
    assert plot_traces.main(["--ip", str(tmp_path / "none.csv"), "--out", str(tmp_path / "x.png")]) == 2
    assert "No such file" in capsys.readouterr().err
