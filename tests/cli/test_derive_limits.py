"""``sylva derive`` at the limits (issue 23): step counts refused up front, naming where they
came from; a derivation the module limit stops says how far it got, and ``--keep-last``
prints the last word that fits; ``-r SEED`` is seed 000's spelling of ``--seed``."""

import pytest

from sylva.cli import main


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def doubling(tmp_path):
    f = tmp_path / "double.lsys"
    f.write_text("axiom = F\nF -> FF\n")
    return f


@pytest.fixture
def stochastic(tmp_path):
    f = tmp_path / "maybe.lsys"  # may stay F: the limit is met during the derivation
    f.write_text("axiom = F\nF ->(3) FF\nF -> F\n")
    return f


@pytest.mark.parametrize("n", ["100000000000000000000000", "1e23", "100001"])
def test_dash_n_above_the_maximum_is_an_argument_error(capsys, doubling, n):
    with pytest.raises(SystemExit) as e:
        main(["derive", str(doubling), "-n", n])
    err = capsys.readouterr().err
    assert e.value.code == 2 and "argument -n/--steps" in err and "0 to 100,000" in err


def test_steps_in_the_file_above_the_maximum_name_the_line(capsys, tmp_path):
    f = tmp_path / "forever.lsys"
    f.write_text("axiom = F\nsteps = 1e23\nF -> F\n")
    code, out, err = run(capsys, "derive", f)
    assert code == 2 and out == "" and f"{f}:2:9:" in err and "Traceback" not in err


def test_more_steps_than_the_limit_allows_names_dash_n(capsys, doubling):
    code, out, err = run(capsys, "derive", doubling, "-n", 40, "--limit", 1000)
    assert code == 2 and out == ""
    assert "-n 40:" in err and "by step 10" in err and "at most 9 steps" in err



@pytest.mark.parametrize("command, out", [("render", "x.png"), ("animate", "x.gif")])
def test_render_and_animate_name_dash_n_and_take_limit(capsys, doubling, tmp_path, command, out):
    # 2**10 = 1,024 modules at step 10 > 1,000: the same refusal as derive's, before any drawing
    code, _, err = run(capsys, command, doubling, "-n", 40, "--limit", 1000, "-o", tmp_path / out)
    assert code == 2 and "-n 40:" in err and "at most 9 steps" in err
    assert not (tmp_path / out).exists()

def test_more_steps_than_the_limit_allows_names_the_steps_line(capsys, tmp_path):
    f = tmp_path / "s.lsys"
    f.write_text("steps = 30\naxiom = F\nF -> FF\n")
    code, _, err = run(capsys, "derive", f, "--limit", 1000)
    assert code == 2 and f"{f}:1:9: steps = 30:" in err and "^" in err


def test_keep_last_prints_the_last_word_under_the_limit(capsys, doubling):
    code, out, err = run(capsys, "derive", doubling, "-n", 40, "--limit", 1000, "--keep-last")
    assert code == 0 and out == "F" * 512 + "\n"
    assert "deriving at most 9 steps (--keep-last)" in err


def test_a_stopped_derivation_says_how_far_it_got(capsys, stochastic):
    code, out, err = run(capsys, "derive", stochastic, "-n", 40, "--limit", 1000, "-r", 1)
    assert code == 2 and out == ""
    assert "the derivation stopped after" in err and "of 40 steps, with" in err
    assert "--keep-last" in err


def test_keep_last_writes_the_word_the_limit_stopped_at(capsys, stochastic):
    code, out, err = run(capsys, "derive", stochastic, "-n", 40, "--limit", 1000, "-r", 1,
                         "--keep-last", "--stats")  # fmt: skip
    assert code == 0
    step = int(out.split("step: ")[1].split()[0])
    modules = int(out.split("modules: ")[1].split()[0])
    assert 0 < step < 40 and 500 < modules <= 1000
    assert f"stopped after {step} of 40 steps, with {modules:,} modules" in err
    # the same word as a derivation of exactly that many steps
    code, again, _ = run(capsys, "derive", stochastic, "-n", step, "--seed", 1, "--stats")
    assert f"modules: {modules}\n" in again


def test_dash_r_is_seed(capsys, tmp_path):
    f = tmp_path / "bush.txt"  # seed 000's stochastic bush, as its CLI runs it
    f.write_text("iteration: 6\nangle: 22.5\naxiom: F\nrule: F -> F[+F]F\nrule: F -> F[-F]F\n"
                 "rule: F -> F\n")  # fmt: skip
    words = {run(capsys, "derive", f, "-r", s)[1] for s in (1, 2, 3)}
    assert len(words) == 3
    assert run(capsys, "derive", f, "-r", 2)[1] == run(capsys, "derive", f, "--seed", 2)[1]


def test_export_keep_last_writes_the_last_word_that_fits(capsys, doubling, tmp_path):
    out = tmp_path / "plant.obj"
    code, _, err = run(capsys, "export", doubling, "-o", out, "-n", 40, "--limit", 1000)
    assert code == 2 and "-n 40:" in err and not out.exists()
    code, _, err = run(capsys, "export", doubling, "-o", out, "-n", 40, "--limit", 1000,
                       "--keep-last")  # fmt: skip
    assert code == 0 and out.exists() and "(512 modules," in err


def test_export_dash_r_is_seed(capsys, stochastic, tmp_path):
    (tmp_path / "a").mkdir(), (tmp_path / "b").mkdir()
    a, b = tmp_path / "a" / "plant.obj", tmp_path / "b" / "plant.obj"
    assert run(capsys, "export", stochastic, "-o", a, "-n", 6, "-r", 5)[0] == 0
    assert run(capsys, "export", stochastic, "-o", b, "-n", 6, "--seed", 5)[0] == 0
    assert a.read_bytes() == b.read_bytes()


@pytest.mark.parametrize("command", ["derive", "render", "animate", "export"])
@pytest.mark.parametrize("value", ["-5", "0", "x"])
def test_a_limit_that_is_not_a_positive_whole_number_is_an_argument_error(capsys, doubling,
                                                                         command, value):
    argv = [command, str(doubling), "--limit", value]
    if command != "derive":
        argv += ["-o", "x.png" if command == "render" else "x.gif" if command == "animate"
                 else "x.glb"]  # fmt: skip
    with pytest.raises(SystemExit) as e:
        main(argv)
    err = capsys.readouterr().err
    assert e.value.code == 2 and "argument --limit" in err and "Traceback" not in err


def test_a_misspelt_environment_is_an_error_even_without_communication_modules(capsys,
                                                                               doubling):
    code, out, err = run(capsys, "derive", doubling, "--environment", "ligth")
    assert code == 2 and out == "" and "unknown environment 'ligth'" in err
