"""The Studio's pieces without a server: caps, workspace confinement, sessions, help, CLI."""

from __future__ import annotations

import pytest

from sylva.errors import SylvaError
from sylva.studio import Limits
from sylva.studio._help import help_tables
from sylva.studio._sessions import Session, SessionStore, TooManySessions
from sylva.studio._work import (
    CapError,
    advance,
    camera_hint,
    load_program,
    mesh,
    new_derivation,
    word_page,
)
from sylva.studio._workspace import Workspace, WorkspaceError, decode


def session_of(text: str, limits: Limits, **kw) -> Session:
    s = Session("x" * 20)
    s.program = load_program(text, dialect=None, filename=None)
    s.derivation = new_derivation(s.program, seed=1, limits=limits, trace=kw.get("trace", False))
    return s


def test_a_step_estimated_past_the_time_cap_is_refused():
    limits = Limits(time_cap=0.5)
    s = session_of("axiom = F\nF -> FFFF\n", limits)
    advance(s, 8, Limits(time_cap=600))  # 65,536 modules
    # pretend the last step was slow: the next one (4x the modules) is estimated past the cap
    s.last_step = (0.3, 16_384, 65_536)
    with pytest.raises(CapError) as exc:
        advance(s, 1, limits)
    assert exc.value.kind == "time" and "estimated" in str(exc.value)
    assert s.derivation.step == 8  # nothing lost, nothing half-done


def test_the_time_cap_stops_a_long_request_between_steps():
    limits = Limits(time_cap=0.05, max_steps=10_000)
    s = session_of("axiom = F\nF -> F\n", limits, trace=True)
    with pytest.raises(CapError) as exc:
        advance(s, 10_000, limits)
    assert exc.value.kind == "time" and "reached" in str(exc.value)
    assert 0 < s.derivation.step < 10_000


def test_stop_and_module_cap():
    limits = Limits(max_modules=1000)
    s = session_of("axiom = F\nF -> FF\n", limits)
    s.cancel.set()
    with pytest.raises(CapError) as exc:
        advance(s, 3, limits)
    assert exc.value.kind == "stopped"
    s.cancel.clear()
    with pytest.raises(CapError) as exc:
        advance(s, 20, limits)
    assert exc.value.kind == "modules" and s.derivation.step == 9
    with pytest.raises(CapError):
        advance(s, limits.max_steps + 1, limits)


def test_meshing_stops_at_the_time_cap_between_phases():
    from sylva.studio._scheduler import run_through
    from sylva.studio._work import meshing

    limits = Limits(time_cap=0.5)
    s = session_of("axiom = F\nF -> F[+F]F\n", limits)
    advance(s, 3, limits)
    with pytest.raises(CapError) as exc:
        run_through(meshing(s, limits, clock=lambda: 0.6))  # the work took 0.6 s so far
    assert exc.value.kind == "time" and "time cap of 0.5 s" in str(exc.value)
    assert s.drawn is None
    s.cancel.set()  # Stop, or a newer request of the session
    with pytest.raises(CapError) as exc:
        run_through(meshing(s, limits))
    assert exc.value.kind == "stopped"
    s.cancel.clear()
    assert run_through(meshing(s, limits)).step == 3


def test_triangle_cap_lowers_the_sides():
    limits = Limits(max_triangles=2000)
    s = session_of("detail = 25\naxiom = F\nF -> FF\n", limits)
    advance(s, 6, limits)  # 64 segments
    drawn = mesh(s, limits)
    assert drawn.sides < 25 and drawn.triangles <= 2000
    # a branching plant (a joint at every segment): the cap holds, not 1.5x of it
    b = session_of("detail = 25\naxiom = F\nF -> F[+F]F[-F]F\n", limits)
    advance(b, 3, limits)  # 125 segments
    drawn_b = mesh(b, limits)
    assert 1000 < drawn_b.triangles <= 2000
    page = word_page(s, 60, 10, limits)
    assert page["start"] == 60 and page["modules"] == ["F"] * 4


def test_camera_hint_per_dialect():
    assert camera_hint(load_program("axiom = F\nF -> F+F\n", dialect=None, filename=None)) \
        == "2d"
    assert camera_hint(load_program("axiom = F\nF -> F\\F\n", dialect=None, filename=None)) \
        == "perspective"
    classic = "iteration: 2\nangle: 30\naxiom: F\nrule: F -> F[&F]F\n"
    assert camera_hint(load_program(classic, dialect=None, filename=None)) == "perspective"
    with pytest.raises(SylvaError):
        load_program("axiom = F", dialect="python", filename=None)


def test_workspace_confinement(tmp_path):
    ws = Workspace(tmp_path)
    assert ws.resolve("a/b.lsys") == tmp_path.resolve() / "a" / "b.lsys"
    for bad, status in (("../x.lsys", 403), ("/abs.lsys", 403), ("a/../../x.lsys", 403),
                        (".git/config.lsys", 403), ("x.exe", 400), ("a\\b.lsys", 400),
                        ("c:x.lsys", 400), ("x\x00.lsys", 400), (None, 400), ("", 400)):
        with pytest.raises(WorkspaceError) as exc:
            ws.resolve(bad)
        assert exc.value.status == status, bad
    assert ws.write("d/e.lsys", "axiom = F\n", overwrite=False) == "d/e.lsys"
    with pytest.raises(WorkspaceError):
        ws.write("d/e.lsys", "x", overwrite=False)
    assert ws.read("d/e.lsys", 100) == "axiom = F\n"
    with pytest.raises(WorkspaceError) as exc:
        ws.read("d/e.lsys", 3)
    assert exc.value.status == 413
    assert [f["path"] for f in ws.list()] == ["d/e.lsys"]
    assert not list(tmp_path.glob("d/.sylva-*"))  # no temporary file left behind


def test_decode_detects_the_encoding():
    text = "# příklad jednoduchého L-systému\naxiom = F\n"
    assert decode(text.encode("utf-8")) == text
    assert decode(b"\xef\xbb\xbf" + text.encode("utf-8")) == text
    assert decode(text.encode("cp1250")) == text
    assert decode(text.encode("utf-16")) == text


def test_sessions_are_made_on_request_and_only_idle_ones_are_evicted():
    store = SessionStore(capacity=2, idle_timeout=60)
    assert store.get("a" * 20) is None and len(store) == 0  # asking makes nothing
    a, b = store.create(), store.create()
    assert store.get(a.id) is a and a.id != b.id
    a.derivation = object()
    # full of active sessions: the new client is refused, nobody is evicted
    with pytest.raises(TooManySessions) as exc:
        store.create()
    assert 1 <= exc.value.retry_after <= 30
    assert a.id in store and b.id in store and not a.cancel.is_set()
    a.last_used -= 61  # a went idle
    c = store.create()
    assert a.id not in store and b.id in store and c.id in store
    assert a.cancel.is_set() and a.derivation is None  # released, memory with it
    b.last_used -= 120
    b.job = object()  # idle for long, but a job of it is running: kept
    assert store.evict_idle() == 0 and b.id in store
    b.job = None
    assert store.evict_idle() == 1 and len(store) == 1
    assert SessionStore.valid_id(SessionStore.new_id())
    assert not SessionStore.valid_id("short") and not SessionStore.valid_id("x" * 20 + ";")


def test_help_tables_follow_the_turtle_tables():
    from sylva.turtle import TABLES

    for turtle in ("lsys", "abop", "classic", "engine"):
        h = help_tables(turtle)
        assert [x["symbol"] for x in h["symbols"]] == list(TABLES[turtle])
        assert all(x["meaning"] for x in h["symbols"])
    assert help_tables("nonsense")["turtle"] == "lsys"


def test_cli_registers_studio(tmp_path, monkeypatch):
    from sylva.cli import build_parser
    from sylva.cli import studio as cli_studio

    args = build_parser().parse_args(["studio", "--port", "0", "--no-browser",
                                      "--workspace", str(tmp_path), "--max-modules", "10"])
    assert args.func is cli_studio.run and args.port == 0 and args.no_browser
    seen = {}
    monkeypatch.setattr("sylva.studio.serve", lambda ws, **kw: seen.update(ws=ws, **kw))
    (tmp_path / "p.lsys").write_text("axiom = F\n")
    args = build_parser().parse_args(["studio", str(tmp_path / "p.lsys"), "--no-browser"])
    assert cli_studio.run(args) == 0
    assert seen["start_file"] == "file:p.lsys" and seen["ws"] == tmp_path.resolve()
    assert seen["open_browser"] is False
    args = build_parser().parse_args(["studio", "koch-snowflake", "--no-browser",
                                      "--workspace", str(tmp_path)])
    cli_studio.run(args)
    assert seen["start_file"] == "example:01-koch-snowflake"
    with pytest.raises(SylvaError):
        cli_studio.run(build_parser().parse_args(["studio", "--port", "70000"]))
