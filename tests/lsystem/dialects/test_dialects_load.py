"""load / loads / load_all / detect: paths, texts, encodings and dialect dispatch."""

from __future__ import annotations

import io

import pytest
from _dialect_examples import ACACIA, BUSH_WITH_LEAVES, SOURCE_CODE_2, TEST_VECTOR

from sylva.errors import LSystemSemanticError, LSystemSyntaxError
from sylva.lsystem.dialects import DIALECTS, detect, load, load_all, loads


@pytest.mark.parametrize(
    ("text", "dialect"),
    [
        (SOURCE_CODE_2, "lsys"),
        (BUSH_WITH_LEAVES, "classic"),
        (ACACIA, "engine"),
        (TEST_VECTOR, "engine"),
        ("# header comment\n\n  1 2 3\nX\n", "engine"),
        ("; comment\naxiom: F\n", "classic"),
        ("rule: F -> FF\n", "classic"),
        ("axiom = F\n", "lsys"),
        ("", "lsys"),
        ("1 2\naxiom = F", "lsys"),
    ],
)
def test_detect_by_content(text, dialect):
    assert detect(text) == dialect
    assert detect(text, "plant.txt") == dialect
    assert detect(text, "plant.ls") == dialect


def test_lsys_extension_wins():
    assert detect(ACACIA, "plant.lsys") == "lsys"
    assert detect(BUSH_WITH_LEAVES, "x/y/PLANT.LSYS") == "lsys"


def test_load_dispatches_by_extension_then_content(tmp_path):
    lsys = tmp_path / "t14.lsys"
    lsys.write_text(SOURCE_CODE_2, encoding="utf-8")
    classic = tmp_path / "bush.txt"
    classic.write_text(BUSH_WITH_LEAVES, encoding="utf-8")
    acacia = tmp_path / "acacia.ls"
    acacia.write_text(ACACIA, encoding="utf-8")
    for path, dialect in [(lsys, "lsys"), (classic, "classic"), (acacia, "engine")]:
        for source in (path, str(path)):
            p = load(source)
            assert p.dialect == dialect and p.filename == str(path) and p.name == path.stem
    # an engine file named .lsys is read as .lsys (and fails there, naming the file)
    wrong = tmp_path / "acacia.lsys"
    wrong.write_text(ACACIA, encoding="utf-8")
    with pytest.raises(LSystemSyntaxError) as info:
        load(wrong)
    assert info.value.filename == str(wrong) and info.value.line == 1
    assert load(wrong, dialect="engine") == load(acacia)


def test_dialect_can_be_forced_and_has_aliases():
    assert loads("axiom: F", dialect="classic").dialect == "classic"
    assert loads("axiom = F", dialect="lsysvis").dialect == "lsys"
    with pytest.raises(LSystemSyntaxError):
        loads(BUSH_WITH_LEAVES, dialect="lsys")
    with pytest.raises(ValueError, match="unknown dialect 'logo'"):
        loads("axiom = F", dialect="logo")
    assert sorted(DIALECTS) == ["classic", "cpfg", "engine", "lsys"]
    assert loads("Axiom: F\nF --> FF", dialect="lstudio").dialect == "cpfg"


@pytest.mark.parametrize("encoding", ["utf-8", "utf-8-sig", "utf-16", "cp1250"])
def test_encodings_are_detected(tmp_path, encoding):
    path = tmp_path / "bush.txt"
    path.write_bytes(BUSH_WITH_LEAVES.encode(encoding))
    p = load(path)
    assert p == loads(BUSH_WITH_LEAVES) and p.dialect == "classic"


def test_bytes_and_file_objects():
    assert load(SOURCE_CODE_2.encode("utf-8")) == loads(SOURCE_CODE_2)
    assert load(io.StringIO(SOURCE_CODE_2)) == loads(SOURCE_CODE_2)
    assert load(io.BytesIO(ACACIA.encode())) == loads(ACACIA)
    with pytest.raises(TypeError):
        load(42)


def test_text_that_looks_like_a_missing_path(tmp_path):
    with pytest.raises(LSystemSyntaxError, match="no such file"):
        load(str(tmp_path / "missing.lsys"))
    with pytest.raises(FileNotFoundError):
        load(tmp_path / "missing.lsys")


def test_load_all_and_index():
    text = ACACIA + TEST_VECTOR
    assert len(load_all(text)) == 2
    assert load_all(SOURCE_CODE_2) == [loads(SOURCE_CODE_2)]
    assert load(text, index=-1) == loads(TEST_VECTOR)
    with pytest.raises(LSystemSemanticError, match="out of range"):
        load(text, index=2)


def test_filename_is_used_in_errors_of_texts():
    with pytest.raises(LSystemSyntaxError) as info:
        loads("axiom = F\nF -> [", filename="editor buffer")
    assert str(info.value).startswith("editor buffer:2:6:")


def test_line_endings_and_bom():
    text = "\ufeffrot = 30\r\naxiom = F\r\nF -> FF\r\n"
    p = loads(text)
    assert p.settings == {"rot": 30.0} and p.rules[0].span.line == 3
    assert loads("\ufeffaxiom: F\r\nrule: F -> FF").dialect == "classic"


def test_detect_skips_a_byte_order_mark():
    assert detect("\ufeff45 45 0.8\nX\n") == "engine"
    assert loads("\ufeff45 45 0.8\nX\n").dialect == "engine"
