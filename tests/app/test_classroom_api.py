"""Classroom mode's HTTP side (issue 26), in process: nothing without the join code (every route, a wrong
code too), teacher actions refused to students, students unable to see or change each other's rulebases and
runs, names kept as typed text, each bound answered with a message naming it, the tournament's round fair
(every entry on the same starts) and kept in the store across a restart, its CSV safe in a spreadsheet.
The real `serve --class` on a network address, its websocket and its browser pages: test_classroom_serve.py."""

from __future__ import annotations

import csv
import io
import re
import time

import pytest
from fastapi.testclient import TestClient

from soccer_lab.app.web.api import create_app
from soccer_lab.app.web.classroom.admission import (JOIN_COOKIE, STUDENT_COOKIE, TEACHER_COOKIE, WRONG_GUESS_COST,
                                                Classroom)
from soccer_lab.app.web.classroom.rate import RateLimiter
from soccer_lab.app.web.classroom.settings import ENTRY_MAX_CHARACTERS, REQUEST_BURST, REQUESTS_PER_SECOND
from soccer_lab.app.web.classroom.tournament import Tournament, play_round
from soccer_lab.app.web.origins import SiteAddresses
from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.runs.manager import RunManager
from soccer_lab.app.store import Store
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rules_text

ADDRESS, PORT = "192.0.2.2", 8000  # the documentation network's address: the class's LAN address here
CLASS_URL = f"http://{ADDRESS}:{PORT}"
CODE, TOKEN = "K7PQ2M", "the-teachers-token-0123456789"
KICKER = "if Ball is At then Kick Straight High\nif Ball is not At then GoToBall VeryHigh"
SMALL_RUN = {"ga": {"population_size": 4, "max_generations": 2, "workers": 1},
             "game": {"max_ticks": 60, "games_per_evaluation": 1}}
SMALL_GAME = GameConfig(max_ticks=200)


class Class:
    """A class served in process: its app, store and a browser (TestClient, with its own cookies) per visitor."""

    def __init__(self, folder):
        self.folder = folder
        self.store = Store(folder / DATABASE_FILE)
        self.runs = RunManager(self.store, folder, queue_runs=True)  # as serve --class
        self.classroom = Classroom(self.store, CODE, TOKEN, CLASS_URL)
        self.runs.student_bounds = self.classroom.settings.check_student_run
        self.tournament = Tournament(self.store, Vocabulary.default(), SMALL_GAME, lambda: self.classroom.settings)
        site = SiteAddresses.of("0.0.0.0", {PORT}, {PORT}, also=(ADDRESS,))
        self.app = create_app(self.store, self.runs, site=site, ui_websocket=f"ws://0.0.0.0:8080",
                              classroom=self.classroom, tournament=self.tournament)
        self.clients: list[TestClient] = []

    def browser(self) -> TestClient:
        # X-Soccer-Lab: what a script sends with a body-less POST or DELETE (issue 25's check against forms)
        client = TestClient(self.app, base_url=CLASS_URL, raise_server_exceptions=False, follow_redirects=False,
                            headers={"X-Soccer-Lab": "1"})
        client.__enter__()
        self.clients.append(client)
        return client

    def student(self, name: str) -> TestClient:
        """A pupil's browser, joined under `name`, its cookie come back as with the join page's next page (the place
        is claimed; admitted in process, so the tests' rate budgets stay whole)."""
        client = self.browser()
        joined = client.post("/api/class/join", json={"code": CODE, "name": name})
        assert joined.status_code == 200, joined.text
        assert self.classroom.admit("; ".join(f"{k}={v}" for k, v in client.cookies.items())) is not None
        return client

    def teacher(self) -> TestClient:
        client = self.browser()
        assert client.post("/api/class/teacher", json={"token": TOKEN}).status_code == 200
        return client

    def close(self):
        for client in self.clients:
            client.__exit__(None, None, None)
        self.runs.shutdown()
        self.tournament.close(60)
        self.store.close()


@pytest.fixture
def room(tmp_path):
    room = Class(tmp_path)
    yield room
    room.close()


def every_route(app) -> list[tuple[str, str]]:
    """(method, path) of every API route, its ids filled in, and the pages."""
    found = [("GET", "/"), ("GET", "/index.html"), ("GET", "/ui/"), ("GET", "/docs"), ("GET", "/openapi.json")]
    for path, operations in app.openapi()["paths"].items():
        found += [(method.upper(), re.sub(r"\{[^}]+\}", "1", path)) for method in operations]
    return found


def test_every_route_is_refused_without_the_code_and_with_a_wrong_one(room):
    room.classroom.rate = RateLimiter(10, 10_000)  # this test is about the code, not the rate
    stranger, wrong = room.browser(), room.browser()
    wrong.cookies.set(JOIN_COOKIE, "WRONG1")
    wrong.cookies.set(TEACHER_COOKIE, "guess")
    routes = [r for r in every_route(room.app) if r[1] not in ("/api/class/join", "/api/class/teacher")]
    assert len(routes) > 40  # the whole API, not a few
    for client in (stranger, wrong):
        for method, path in routes:
            # as a script would send it (JSON, the app's header): past issue 25's checks, only the code is missing
            response = client.request(method, path, json={} if method in ("POST", "PUT", "PATCH") else None)
            if method == "GET" and not path.startswith("/api/"):
                assert response.status_code == 303 and response.headers["location"].startswith("/join.html?next="), \
                    (method, path, response.status_code)
            else:
                assert response.status_code == 401 and "join the class first" in response.json()["detail"], \
                    (method, path, response.status_code)
            assert response.headers["x-frame-options"] == "DENY"
    assert room.store.list_rulebases() == [] and room.store.list_students() == []
    # What is open to all: the join page and what it shows
    assert stranger.get("/join.html").status_code == 200 and stranger.get("/style.css").status_code == 200


def test_a_page_asked_for_before_joining_comes_back_after_it(room):
    response = room.browser().get("/ui/?pitch=abc")
    assert response.status_code == 303
    assert response.headers["location"] == "/join.html?next=%2Fui%2F%3Fpitch%3Dabc"


def test_joining_needs_the_code_and_gives_httponly_strict_cookies(room):
    client = room.browser()
    refused = client.post("/api/class/join", json={"code": "WRONG1", "name": "Ada"})
    assert refused.status_code == 400 and "not this class's join code" in refused.json()["detail"]
    assert "set-cookie" not in refused.headers
    joined = client.post("/api/class/join", json={"code": CODE.lower(), "name": "Ada"})  # as typed on a phone
    assert joined.status_code == 200 and joined.json() == {"name": "Ada", "teacher": False}
    cookies = joined.headers.get_list("set-cookie")
    assert {c.split("=")[0] for c in cookies} == {JOIN_COOKIE, STUDENT_COOKIE}
    assert all("HttpOnly" in c and "SameSite=Strict" in c for c in cookies)
    assert client.get("/api/class").json()["you"] == {"name": "Ada", "teacher": False}
    assert client.get("/").status_code == 200
    # The same name again (another browser) is refused: names are the class's table's rows
    other = room.browser().post("/api/class/join", json={"code": CODE, "name": " ada "})
    assert other.status_code == 400 and "taken" in other.json()["detail"]
    teacher = room.browser().post("/api/class/teacher", json={"token": "not-it"})
    assert teacher.status_code == 400 and "teacher token" in teacher.json()["detail"]


@pytest.mark.parametrize("name, refusal", [
    ("A\u202eB", "bidirectional"), ("line\nbreak", "control character"), ("x" * 41, "at most 40 characters"),
    ("Teacher", "the teacher's"), ("   ", "empty"),
])
def test_display_names_are_one_line_of_plain_text(room, name, refusal):
    response = room.browser().post("/api/class/join", json={"code": CODE, "name": name})
    assert response.status_code == 400 and refusal in response.json()["detail"], response.text


def test_teacher_actions_are_refused_to_students(room):
    teacher = room.teacher()
    ada = room.student("Ada")
    assert ada.post("/api/class/entries", json={"text": KICKER}).status_code == 201
    entry = ada.get("/api/class/entries").json()[0]["id"]
    student_id = room.store.list_students()[0].id
    refused = [
        ada.post("/api/class/rounds", json={}),
        ada.delete(f"/api/class/entries/{entry}"),
        ada.put("/api/class/settings", json={"starts": 5}),
        ada.get("/api/class/students"),
        ada.delete(f"/api/class/students/{student_id}"),
        ada.post("/api/class/entries", json={"text": KICKER, "name": "GA best"}),  # an entry under another name
    ]
    for response in refused:
        assert response.status_code == 403 and "only the teacher can" in response.json()["detail"], response.text
    assert room.classroom.settings.starts == 20 and len(room.tournament.entries()) == 1 and not room.store.list_rounds()
    # the teacher may do each
    assert teacher.put("/api/class/settings", json={"starts": 3}).json()["starts"] == 3
    assert [s["name"] for s in teacher.get("/api/class/students").json()] == ["Ada"]
    assert teacher.delete(f"/api/class/entries/{entry}").status_code == 204
    assert teacher.delete(f"/api/class/students/{student_id}").status_code == 204
    assert ada.get("/api/class").status_code == 401  # removed: that browser must join again


def test_students_neither_see_nor_change_each_others_rulebases_and_runs(room):
    teacher, ada, ben = room.teacher(), room.student("Ada"), room.student("Ben")
    shared = teacher.post("/api/rulebases", json={"name": "class demo", "text": KICKER}).json()["id"]
    adas = ada.post("/api/rulebases", json={"name": "mine", "text": KICKER}).json()["id"]
    assert [r["id"] for r in ben.get("/api/rulebases").json()] == [shared]
    assert {r["id"] for r in ada.get("/api/rulebases").json()} == {shared, adas}
    assert {r["id"] for r in teacher.get("/api/rulebases").json()} == {shared, adas}
    assert ben.get(f"/api/rulebases/{adas}").status_code == 404
    assert ben.put(f"/api/rulebases/{adas}", json={"text": "if Ball is At then Kick Straight Low"}).status_code == 404
    assert ben.delete(f"/api/rulebases/{adas}").status_code == 404
    deleting_shared = ben.delete(f"/api/rulebases/{shared}")
    assert deleting_shared.status_code == 403 and "only the teacher can" in deleting_shared.json()["detail"]
    assert room.store.get_rulebase(adas).text == KICKER and room.store.get_rulebase(shared).name == "class demo"

    run = ada.post("/api/runs", json=SMALL_RUN)
    assert run.status_code == 201, run.text
    run_id = run.json()["id"]
    assert ben.get("/api/runs").json() == [] and ben.get(f"/api/runs/{run_id}").status_code == 404
    assert ben.post(f"/api/runs/{run_id}/stop").status_code == 404
    assert ben.get(f"/api/runs/{run_id}/statistics").status_code == 404
    assert [r["id"] for r in teacher.get("/api/runs").json()] == [run_id]
    assert teacher.post(f"/api/runs/{run_id}/stop").status_code == 200  # the teacher may stop anyone's
    room.runs.wait(run_id, timeout=120)
    # A run's lineage and populations are as private as the run
    run_id = ada.post("/api/runs", json=SMALL_RUN).json()["id"]
    room.runs.wait(run_id, timeout=120)
    assert ada.get(f"/api/runs/{run_id}/population", params={"generation": 0}).status_code == 200
    for path in (f"/api/runs/{run_id}/lineage", f"/api/runs/{run_id}/population?generation=0"):
        assert ben.get(path).status_code == 404, path
    breeding = {"parents": [{"run_id": run_id, "generation": 0, "index": 0}, {"text": KICKER}], "seed": 1}
    assert ben.post("/api/breed", json=breeding).status_code == 404
    assert ada.post("/api/breed", json=breeding).status_code == 200


def test_a_students_run_is_bounded_with_a_message_naming_the_bound(room):
    ada = room.student("Ada")
    too_many = ada.post("/api/runs", json={"ga": {"population_size": 200, "max_generations": 100}})
    assert too_many.status_code == 409
    assert "a student's run plays at most 5,000" in too_many.json()["detail"]
    too_long = ada.post("/api/runs", json={"ga": {"population_size": 4, "max_generations": 2},
                                           "game": {"max_ticks": 5000}})
    assert too_long.status_code == 409 and "over the class's 1000" in too_long.json()["detail"]
    # counting behaviours plays every new chromosome on more starts: 50 x 25 is 1,250 games, x (1 + 16) is 21,250
    counting = ada.post("/api/runs", json={"ga": {"population_size": 50, "max_generations": 25,
                                                  "behaviour_seeds": 16}})
    assert counting.status_code == 409 and "up to 21,250 games" in counting.json()["detail"]
    assert "16 behaviour seeds" in counting.json()["detail"]
    assert room.store.list_runs() == []


def test_third_pupil_start_is_queued_not_refused(room):
    """The class shares the machine's cores: a Start that finds them busy waits its turn (issue 35), and the
    pupil reads their place and an estimate in the run's record."""
    room.runs.max_concurrent_runs = 1
    ada, ben = room.student("Ada"), room.student("Ben")
    long_run = ada.post("/api/runs", json={"ga": {"population_size": 50, "max_generations": 100}})  # 5,000 games
    assert long_run.status_code == 201 and long_run.json()["status"] == "running", long_run.text
    waiting = ben.post("/api/runs", json=SMALL_RUN)
    assert waiting.status_code == 201 and waiting.json()["status"] == "queued", waiting.text
    place = ben.get(f"/api/runs/{waiting.json()['id']}").json()["queue"]
    assert place["position"] == 1 and place["queued"] == 1 and place["run_seconds"] > 0 and place["wait_seconds"] > 0
    again = ben.post("/api/runs", json=SMALL_RUN)  # one run each: told where the first one is
    assert again.status_code == 409 and "is queued (1st in line of 1" in again.json()["detail"]
    assert ada.post(f"/api/runs/{long_run.json()['id']}/stop").status_code == 200
    assert room.runs.wait(waiting.json()["id"], timeout=120).status == "finished"
    assert ben.get(f"/api/runs/{waiting.json()['id']}").json()["queue"] is None


def test_a_pupil_cancels_only_their_own_queued_run_and_the_teacher_any(room):
    room.runs.max_concurrent_runs = 1
    ada, ben, cyd, teacher = room.student("Ada"), room.student("Ben"), room.student("Cyd"), room.teacher()
    running = ada.post("/api/runs", json={"ga": {"population_size": 50, "max_generations": 100}}).json()
    bens, cyds = (client.post("/api/runs", json=SMALL_RUN).json() for client in (ben, cyd))
    assert (bens["status"], cyds["status"]) == ("queued", "queued")
    assert cyd.get(f"/api/runs/{cyds['id']}").json()["queue"]["position"] == 2
    assert ada.post(f"/api/runs/{bens['id']}/stop").status_code == 404  # another's run does not exist for her
    cancelled = ben.post(f"/api/runs/{bens['id']}/stop")
    assert cancelled.status_code == 200 and cancelled.json()["status"] == "stopped", cancelled.text
    assert cyd.get(f"/api/runs/{cyds['id']}").json()["queue"]["position"] == 1  # moved up
    for run in (cyds, running):  # the teacher cancels a queued run and stops a running one
        assert teacher.post(f"/api/runs/{run['id']}/stop").json()["status"] == "stopped"
    assert not any(room.runs.is_pending(run["id"]) for run in (running, bens, cyds))


def frozen_rate(room) -> None:
    """The class's own rate and burst, on a clock that stands still: no refill however slow the machine."""
    room.classroom.rate = RateLimiter(REQUESTS_PER_SECOND, REQUEST_BURST, clock=lambda: 0.0)


def test_each_visitors_request_rate_is_bounded(room):
    ada, ben = room.student("Ada"), room.student("Ben")
    frozen_rate(room)
    answers = [ada.get("/api/class").status_code for _ in range(REQUEST_BURST + 5)]
    assert answers == [200] * REQUEST_BURST + [429] * 5
    limited = ada.get("/api/class")
    assert limited.status_code == 429 and int(limited.headers["retry-after"]) >= 1
    assert "too many requests" in limited.json()["detail"]
    assert ben.get("/api/class").status_code == 200  # one pupil's flood is not another's


def test_guessing_the_join_code_is_slowed_down(room):
    frozen_rate(room)
    client = room.browser()
    answers = [client.post("/api/class/join", json={"code": f"GUESS{i}", "name": "x"}).status_code
               for i in range(REQUEST_BURST // WRONG_GUESS_COST + 2)]
    assert answers == [400] * (REQUEST_BURST // WRONG_GUESS_COST) + [429] * 2


def test_a_mistyped_code_does_not_lock_out_pupils_joining_from_one_address(room):
    """CI found it: the teacher's mistyped sign-in and a pupil's mistyped code, from one address, spent its
    burst, and the pupil's right code was refused (429) so the join page never moved on."""
    frozen_rate(room)
    client = room.browser()
    assert client.post("/api/class/teacher", json={"token": "NOT-THE-TOKEN"}).status_code == 400
    assert client.post("/api/class/join", json={"code": "WRONG1", "name": "Ada"}).status_code == 400
    for i in range(REQUEST_BURST - 2 * WRONG_GUESS_COST - 10):  # the rest of the burst, but for ten
        assert room.browser().post("/api/class/join", json={"code": CODE, "name": f"pupil{i}"}).status_code == 200
    assert client.post("/api/class/join", json={"code": CODE, "name": "Ada"}).status_code == 200


def test_an_entry_is_bounded_and_must_parse(room):
    ada = room.student("Ada")
    huge = ada.post("/api/class/entries", json={"text": "if Ball is At then Kick Straight High\n" * 600})
    assert huge.status_code == 422 and f"at most {ENTRY_MAX_CHARACTERS} characters" in huge.json()["detail"]
    many = ada.post("/api/class/entries", json={"text": "if Ball is At then Kick Straight High\n" * 101})
    assert many.status_code == 422 and "at most 100 rules; this one has 101" in many.json()["detail"]
    bad = ada.post("/api/class/entries", json={"text": "if Ball is Sideways then Kick"})
    assert bad.status_code == 422 and "line 1" in bad.json()["detail"]
    assert room.tournament.entries() == []


def test_a_students_entry_replaces_their_earlier_one_and_others_rules_stay_private(room):
    ada, ben = room.student("Ada"), room.student("Ben")
    ada.post("/api/class/entries", json={"text": KICKER})
    ada.post("/api/class/entries", json={"text": demo_rules_text()})
    ben.post("/api/class/entries", json={"text": KICKER})
    seen_by_ben = ben.get("/api/class/entries").json()
    assert [(e["name"], e["mine"]) for e in seen_by_ben] == [("Ada", False), ("Ben", True)]
    assert seen_by_ben[0]["text"] is None and seen_by_ben[1]["text"] == KICKER
    assert [e.text for e in room.tournament.entries()] == [demo_rules_text(), KICKER]


def wait_for_round(client, count: int, timeout: float = 120.0) -> dict:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        rounds = client.get("/api/class/rounds").json()
        if len(rounds) >= count:
            return rounds[0]
        time.sleep(0.25)
    raise AssertionError("the round's table did not appear")


def test_a_round_plays_every_entry_on_the_same_starts_and_is_kept(room, tmp_path):
    teacher = room.teacher()
    names = ["=HYPERLINK(\"http://x\")", "<img src=x onerror=alert(1)>", "Ben"]
    for name, text in zip(names, [KICKER, KICKER, demo_rules_text()]):
        assert room.student(name).post("/api/class/entries", json={"text": text}).status_code == 201
    assert teacher.post("/api/class/entries", json={"rulebase_id": teacher.post(
        "/api/rulebases", json={"name": "library kicker", "text": KICKER}).json()["id"], "name": "Library"}
    ).status_code == 201
    started = teacher.post("/api/class/rounds", json={"starts": 4, "seed": 11})
    assert started.status_code == 202 and started.json()["entries"] == 4
    table = wait_for_round(teacher, 1)
    assert table["starts"] == 4 and table["seed"] == 11 and len(table["results"]) == 4
    rows = {row["name"]: row for row in table["results"]}
    # The same rules on the same starts score the same: every entry met the same positions
    assert rows[names[0]]["games"] == rows[names[1]]["games"] == rows["Library"]["games"]
    assert [g["seed"] for g in rows["Ben"]["games"]] == [g["seed"] for g in rows["Library"]["games"]]
    ranked = [(r["goals"], r["fitness"]) for r in table["results"]]
    assert ranked == sorted(ranked, key=lambda r: (-r[0], r[1]))
    # ... and as a game played alone: a row's games are the round's own, replayable
    alone = play_round(room.tournament.entries()[2:3], 4, 11, room.tournament.round_game(), Vocabulary.default())
    assert alone[0]["games"] == rows["Ben"]["games"]
    # Everyone sees the table; a student cannot start the next round
    ben = room.clients[3]
    assert ben.get(f"/api/class/rounds/{table['id']}").json()["results"] == table["results"]

    exported = ben.get(table["csv"].replace(CLASS_URL, ""))
    assert exported.status_code == 200 and exported.headers["content-type"].startswith("text/csv")
    cells = list(csv.DictReader(io.StringIO(exported.text)))
    assert len(cells) == 4 and {c["name"] for c in cells} >= {"'=HYPERLINK(\"http://x\")", names[1]}

    # Rounds survive a restart of the store
    room.store.close()
    reopened = Store(tmp_path / DATABASE_FILE)
    try:
        kept = reopened.list_rounds()
        assert len(kept) == 1 and kept[0].results == table["results"]
    finally:
        reopened.close()
        room.store = Store(tmp_path / DATABASE_FILE)
        room.runs.store = room.store


def test_a_round_needs_entries_and_only_one_plays_at_a_time(room):
    teacher = room.teacher()
    empty = teacher.post("/api/class/rounds", json={})
    assert empty.status_code == 422 and "no entries yet" in empty.json()["detail"]
    room.student("Ada").post("/api/class/entries", json={"text": KICKER})
    too_many = teacher.post("/api/class/rounds", json={"starts": 1000})
    assert too_many.status_code == 422 and "starts" in too_many.text


def test_a_class_has_at_most_max_students(room, monkeypatch):
    import soccer_lab.app.web.classroom.admission as admission

    monkeypatch.setattr(admission, "MAX_STUDENTS", 2)
    room.student("Ada"), room.student("Ben")
    full = room.browser().post("/api/class/join", json={"code": CODE, "name": "Cai"})
    assert full.status_code == 400 and "the class has 2 students, its limit" in full.json()["detail"]
