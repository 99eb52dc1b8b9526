"""The Studio under attack and load: sessions only for the page, bad JSON, superseded and
fair work, and an answer for every one of many clients (127.0.0.1 only, bounded)."""

from __future__ import annotations

import asyncio
import threading

import httpx
import pytest

from .conftest import LiveServer, open_session, page_token

PLANT = "rot = 25.7\naxiom = F\nF -> F[+F]F[-F]F\n"
# a traced step over 40,000 modules takes milliseconds: 1000 of them take seconds
SLOW = "axiom = " + "F" * 40_000 + "\nF -> F\n"


def test_cross_site_requests_make_no_session(live):
    store = live.app.state.studio.sessions
    with live.client() as user:
        assert user.post("/api/load", json={"text": PLANT, "steps": 2}).status_code == 200
        before = len(store)
        # what a page on another site can send: GETs and form posts, without our header
        with httpx.Client(base_url=live.url) as other:
            for i in range(70):
                r = other.get("/api/state" if i % 2 else "/api/mesh")
                assert r.status_code == 401 and r.json()["error"] == "session"
            assert other.post("/api/session", json={}).status_code == 403  # no page token
            r = other.post("/api/session", json={},
                           headers={"x-sylva-page": page_token(live.url),
                                    "origin": "http://evil.example"})
            assert r.status_code == 403
        assert len(store) == before
        assert user.get("/api/state").json()["step"] == 2  # the user's session is there


def test_a_full_store_refuses_the_new_client_and_keeps_the_active_ones(workspace):
    from sylva.studio import Limits

    with LiveServer(workspace, Limits(max_sessions=3)) as srv:
        token = page_token(srv.url)
        users = [open_session(srv.url, token).json()["session"] for _ in range(3)]
        for k, sid in enumerate(users):
            r = httpx.post(srv.url + "/api/load", json={"text": PLANT, "steps": k},
                           headers={"x-sylva-session": sid}, timeout=30)
            assert r.status_code == 200
        for _ in range(10):
            r = open_session(srv.url, token)
            assert r.status_code == 503 and r.json()["error"] == "busy"
            assert 1 <= int(r.headers["retry-after"]) <= 30
        for k, sid in enumerate(users):  # nobody was evicted
            r = httpx.get(srv.url + "/api/state", headers={"x-sylva-session": sid})
            assert r.status_code == 200 and r.json()["step"] == k
        # a page that is closed frees its slot
        httpx.delete(srv.url + "/api/session", headers={"x-sylva-session": users[0]})
        assert open_session(srv.url, token).status_code == 200


@pytest.mark.parametrize("path, body", [
    ("/api/load", b'{"text": "axiom = F\\nF -> FF\\n", "steps": 1e400}'),
    ("/api/load", b'{"text": "axiom = F\\n", "seed": -1e400}'),
    ("/api/load", b'{"text": "axiom = F\\n", "steps": NaN}'),
    ("/api/load", b'{"text": "axiom = F\\n", "steps": 2.5}'),
    ("/api/load", b'{"text": "axiom = F\\n", "overrides": {"x": 1e999}}'),
    ("/api/load", b'{"text": "axiom = F\\n", "dialect": 7}'),
    ("/api/load", b"[" * 100_000 + b"]" * 100_000),
    ("/api/load", b'{"text": ' + b'{"a":' * 50_000 + b"1" + b"}" * 50_001),
    ("/api/load", b'{"text": "axiom = \\ud800\\n"}'),
    ("/api/file", b'{"path": "a.lsys", "text": "\\udfff"}'),
    ("/api/step", b'{"n": 1e400}'),
    ("/api/step", b'{"n": Infinity}'),
    ("/api/pick", b'{"point": [1e400, 0, 0]}'),
    ("/api/export-png", b'{"width": 1e400}'),
    # an integer past the largest float is as out of range as 1e400 (it was a 500: the
    # handlers took it for a number and float() overflowed)
    ("/api/pick", b'{"point": [1' + b"0" * 400 + b', 0, 0]}'),
    ("/api/export-png", b'{"width": 8, "height": 8, "camera": {"yaw": 1' + b"0" * 400 + b"}}"),
    ("/api/export-png", b'{"width": 8, "camera": {"target": [-1' + b"0" * 400 + b", 0, 0]}}"),
    # a point past the float32 mesh's range (its squared distances overflowed: a 500)
    ("/api/pick", b'{"point": [0, 0, 1e300]}'),
    ("/api/load", b'{"text": "rot = 3\\naxiom = F\\n", "overrides": {"rot": 1' + b"0" * 400
     + b"}}"),
])
def test_bad_json_is_a_400_with_a_message(live, path, body):
    with live.client(timeout=30) as c:
        c.post("/api/load", json={"text": PLANT, "steps": 1})
        method = "PUT" if path == "/api/file" else "POST"
        r = c.request(method, path, content=body, headers={"content-type": "application/json"})
        assert r.status_code == 400, r.text
        assert r.json()["message"]


def test_a_newer_request_supersedes_the_running_one(live):
    with live.client(timeout=60) as a:
        assert a.post("/api/load", json={"text": SLOW}).status_code == 200
        result = {}
        worker = threading.Thread(
            target=lambda: result.update(r=a.post("/api/step", json={"n": 1000})))
        worker.start()
        try:
            while live.app.state.studio.scheduler.queued == 0 and not any(
                    s.busy for s in live.app.state.studio.sessions._sessions.values()):
                threading.Event().wait(0.02)
            threading.Event().wait(0.3)
            newer = a.post("/api/step", json={"n": 1})
        finally:
            worker.join(60)
        old = result["r"]
        assert old.status_code == 409 and old.json()["error"] == "superseded"
        assert newer.status_code == 200
        done = newer.json()["step"]
        assert 1 < done < 1000  # the old request's steps were kept, one more on top


def test_a_small_request_is_served_while_four_clients_derive_for_long(live):
    """Four sessions each derive for seconds (as many as the server has workers); a fifth
    client's small derivation and mesh are answered while all four still run.  With first
    come, first served workers it waited for one of them to end."""
    clients = [live.client(timeout=120) for _ in range(5)]
    try:
        for c in clients[:4]:
            assert c.post("/api/load", json={"text": SLOW}).status_code == 200
        heavy = {}
        threads = [threading.Thread(target=lambda c=c, k=k: heavy.update(
            {k: c.post("/api/step", json={"n": 1000})})) for k, c in enumerate(clients[:4])]
        for t in threads:
            t.start()
        threading.Event().wait(0.5)
        small = clients[4]
        r = small.post("/api/load", json={"text": PLANT, "steps": 2})
        m = small.get("/api/mesh")
        running = sum(t.is_alive() for t in threads)
        for c in clients[:4]:
            c.post("/api/stop")
        for t in threads:
            t.join(120)
        assert r.status_code == 200 and r.json()["modules"] == 61
        assert m.status_code == 200 and m.content[:4] == b"glTF"
        assert running == 4, "the small request waited for a heavy one to end"
        assert all(h.status_code == 422 for h in heavy.values())
    finally:
        for c in clients:
            c.close()


def test_many_clients_all_get_an_answer(workspace):
    """60 clients at once on a server with room for 16 sessions and a short wait: every
    request is answered (a result, or 503 with Retry-After), and every client whose
    session was refused gets in after retrying, so nothing it asked for is lost."""
    from sylva.studio import Limits

    limits = Limits(max_sessions=16, max_wait=2.0, max_modules=200_000)
    with LiveServer(workspace, limits) as srv:
        token = page_token(srv.url)

        async def one(k: int) -> dict:
            answers = {"refused": 0, "busy": 0}
            async with httpx.AsyncClient(base_url=srv.url, timeout=60, verify=False) as c:
                while True:
                    r = await c.post("/api/session", json={}, headers={"x-sylva-page": token})
                    if r.status_code == 200:
                        break
                    assert r.status_code == 503 and "retry-after" in r.headers
                    answers["refused"] += 1
                    await asyncio.sleep(0.2)
                c.headers["x-sylva-session"] = r.json()["session"]
                text = f"rot = {10 + k}\naxiom = F\nF -> F[+F]F[-F]F\n"
                for path, body in (("load", {"text": text}), ("step", {"n": 4})):
                    while True:
                        r = await c.post("/api/" + path, json=body)
                        if r.status_code != 503:
                            break
                        assert "retry-after" in r.headers
                        answers["busy"] += 1
                        await asyncio.sleep(0.2)
                    assert r.status_code == 200, r.text
                answers["modules"] = r.json()["modules"]
                answers["rot"] = r.json()["settings"].get("rot")
                await c.delete("/api/session")
            return answers

        async def main():
            return await asyncio.wait_for(asyncio.gather(*(one(k) for k in range(60))), 120)

        results = asyncio.run(main())
    from sylva.lsystem import derive, loads

    want = len(derive(loads(PLANT), 4))
    assert all(r["modules"] == want for r in results)
    assert [r["rot"] for r in results] == [10.0 + k for k in range(60)]
    assert sum(r["refused"] for r in results) > 0  # the store was full at times


def test_a_name_too_long_for_the_system_is_a_400(live):
    """A path of at most 255 characters whose name is over 255 bytes in UTF-8 (the
    system refuses it with ENAMETOOLONG): it was a 500 on save and on open."""
    name = "é" * 200 + ".lsys"
    with live.client(timeout=30) as c:
        r = c.put("/api/file", json={"path": name, "text": PLANT})
        assert r.status_code == 400 and r.json()["error"] == "workspace", r.text
        assert "longer than 255 bytes" in r.json()["message"]
        r = c.get("/api/file", params={"path": name})
        assert r.status_code == 400 and r.json()["error"] == "workspace", r.text
        # a long name that fits is saved
        fits = "é" * 100 + ".lsys"
        assert c.put("/api/file", json={"path": fits, "text": PLANT}).status_code == 200
        assert c.get("/api/file", params={"path": fits}).json()["text"] == PLANT


def test_a_file_in_the_way_of_a_folder_is_a_409(live):
    """Saving sub-path of a file (``plant.lsys/in.lsys``): the folder cannot be made.  It
    was a 500 ("file exists", "not a directory")."""
    with live.client(timeout=30) as c:
        for path in ("plant.lsys/in.lsys", "plant.lsys/a/b.lsys"):
            r = c.put("/api/file", json={"path": path, "text": PLANT, "overwrite": True})
            assert r.status_code == 409 and r.json()["error"] == "workspace", r.text
            assert r.json()["message"].startswith(f"cannot write {path}: "), r.text
        assert (live.workspace / "plant.lsys").is_file()
