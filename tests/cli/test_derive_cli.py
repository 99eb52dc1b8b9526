"""``sylva derive`` and friends, run in-process and as a real subprocess."""

import subprocess
import sys

from sylva.cli import main


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_derive_prints_one_line(capsys, tmp_path):
    f = tmp_path / "algae.lsys"
    f.write_text("axiom = a\na -> ab\nb -> a\n")
    code, out, _ = run(capsys, "derive", str(f), "-n", "5")
    assert code == 0 and out == "abaababaabaab\n"


def test_each_prints_step_zero_first(capsys, tmp_path):
    f = tmp_path / "t1.lsys"
    f.write_text("axiom = a\na -> b\nb -> aa\n")
    code, out, _ = run(capsys, "derive", str(f), "-n", "4", "--each")
    assert out.splitlines() == ["a", "b", "aa", "bb", "aaaa"]


def test_stats(capsys):
    code, out, _ = run(capsys, "derive", "seed000-hilbert-3d", "--stats")
    assert code == 0
    assert "modules: 271" in out and "\n  F\t63" in out and "branch depth: 0" in out


def test_render_word(capsys):
    code, out, _ = run(capsys, "derive", "seed001-source-code-2", "-n", "1", "--render")
    assert out.strip() == "F[+;(0,0.7,0)F]F[-;(0,0.7,0)F]+(20);(0,0.7,0)F"


def test_syntax_error_is_reported_with_caret_and_exit_2(capsys, tmp_path):
    f = tmp_path / "bad.lsys"
    f.write_text("axiom = F\nF -> F[+F\n")
    code, out, err = run(capsys, "derive", str(f))
    assert code == 2 and out == ""
    assert f"{f}:2:" in err and "^" in err and "Traceback" not in err


def test_growth_limit_is_a_clean_error(capsys, tmp_path):
    f = tmp_path / "grow.lsys"
    f.write_text("axiom = F\nF -> FF\n")
    code, _, err = run(capsys, "derive", str(f), "-n", "40", "--limit", "1000")
    assert code == 2 and "limit" in err and "Traceback" not in err


def test_missing_file_is_a_clean_error(capsys):
    code, _, err = run(capsys, "derive", "no/such/file.lsys")
    assert code == 2 and "no such file" in err


def test_python_dash_m_sylva_runs():
    out = subprocess.run(
        [sys.executable, "-m", "sylva", "derive", "koch-snowflake", "-n", "1"],
        capture_output=True, text=True, timeout=120,
    )
    assert out.returncode == 0 and out.stdout.strip() == "F-F++F-F++F-F++F-F++F-F++F-F"


def test_derive_reads_a_named_cpfg_view_file_and_warns_on_stderr(capsys, tmp_path):
    f = tmp_path / "p.l"
    f.write_text("#define N 2\nLsystem: 1\nderivation length: 1\nAxiom: A\n"
                 "A --> F(N)#A\nendlsystem\n")  # fmt: skip
    v = tmp_path / "other.v"
    v.write_text("angle increment: 30\nz buffer: on\n")
    code, out, err = run(capsys, "derive", str(f), "--view", str(v))
    assert code == 0 and out == 'F(2)"#"A\n'
    assert err == f"sylva: warning: {v}:2: view setting 'z buffer' is not honoured (the " \
        "renderer always hides what is behind)\n"


def test_a_view_file_for_a_file_that_is_not_cpfg_is_an_error(capsys, tmp_path):
    f = tmp_path / "a.lsys"
    f.write_text("axiom = a\na -> ab\n")
    v = tmp_path / "a.v"
    v.write_text("angle increment: 30\n")
    code, _, err = run(capsys, "derive", str(f), "--view", str(v))
    assert code == 2 and "view= (a cpfg view file) is for cpfg files" in err


def test_derive_writes_cpfg_parameters_as_the_floats_they_are(capsys, tmp_path):
    # cpfg keeps parameters as 32-bit floats: 2.2 is 2.200000047683716 as a double,
    # written back as 2.2 (and 0.1 + 0.2 as the float 0.3)
    f = tmp_path / "p.l"
    f.write_text("Lsystem: 1\nderivation length: 1\nAxiom: A(2.2)\n"
                 "A(x) --> B(x)C(0.1+0.2)\nendlsystem\n")  # fmt: skip
    code, out, _ = run(capsys, "derive", str(f), "-n", "1")
    assert code == 0 and out == "B(2.2)C(0.3)\n"
