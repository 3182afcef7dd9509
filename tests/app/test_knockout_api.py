"""The class knockout over HTTP (issue 39, "Match day"), in process: a seeded draw (the same seed, the same draw
and matches), byes to the top of the draw, every tie the best of N mirrored matches from seeds derived from the
knockout's, the winners meeting until one is left, pupils reading but not starting, bad input answered 4xx with
what was wrong, the bracket kept in the store across a restart (one left playing marked interrupted), and its
CSV one row per match, safe in a spreadsheet. Games are short (100 ticks a half)."""

from __future__ import annotations

import csv
import io
import time


from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.store import KnockoutStatus, Store
from soccer_lab.app.web.classroom.knockout import (bracket_order, draw_entries, match_seeds, next_pairing,
                                                  tie_winner)
from soccer_lab.app.web.classroom.tournament import Tournament
from soccer_lab.fuzzy.parser import parse_rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.soccer.config import GameConfig
from soccer_lab.soccer.demo import demo_rules_text
from soccer_lab.soccer.match import play_matches
from tests.app.test_classroom_api import CLASS_URL, KICKER, room  # noqa: F401  (the class fixture)

SHORT = 100  # ticks a half
DRIBBLER = "if Ball is At then Kick Straight Low\nif Ball is not At then GoToBall High"
CHASER = "if Ball is not At then GoToBall VeryHigh\nif Ball is At then Kick Left High"
FORMULA_NAME = '=HYPERLINK("http://x")'


def enter(room, count: int):
    """`count` entries (the teacher's, under names), their rules of a few kinds; the teacher's client."""
    teacher = room.teacher()
    rules = [demo_rules_text(), KICKER, DRIBBLER, CHASER]
    names = [FORMULA_NAME, "Ada", "Ben", "<b>Cai</b>", "Dee", "Eve"]
    for i in range(count):
        made = teacher.post("/api/class/entries", json={"text": rules[i % len(rules)], "name": names[i]})
        assert made.status_code == 201, made.text
    return teacher


def wait_for_knockout(client, knockout_id: int, timeout: float = 120.0) -> dict:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        knockout = client.get(f"/api/class/knockouts/{knockout_id}").json()
        if knockout["status"] != "playing":
            return knockout
        time.sleep(0.2)
    raise AssertionError(f"knockout {knockout_id} still playing after {timeout} s")


def test_bracket_order_gives_byes_to_the_top_of_the_draw():
    assert bracket_order(8) == [1, 8, 4, 5, 2, 7, 3, 6]
    # 5 entries in 8 places: the places 6, 7, 8 are byes, met by draw numbers 3, 2, 1
    pairs = list(zip(bracket_order(8)[::2], bracket_order(8)[1::2]))
    assert sorted(top for top, other in pairs if other > 5) == [1, 2, 3]


def test_a_tie_level_on_wins_goes_by_goal_difference_then_the_higher_place_in_the_draw():
    assert tie_winner(4, 5, [1, 2], [3, 2]) == (5, "matches won")
    assert tie_winner(4, 5, [1, 1], [3, 2]) == (4, "goal difference")
    assert tie_winner(4, 5, [0, 0], [1, 1]) == (4, "higher in the draw")
    assert tie_winner(5, 4, [0, 0], [0, 0]) == (4, "higher in the draw")


def test_a_knockout_is_a_seeded_draw_with_byes_and_best_of_n_ties_reproduced_by_its_seed(room):
    teacher = enter(room, 5)
    started = teacher.post("/api/class/knockouts", json={"best_of": 3, "seed": 7, "max_ticks": SHORT})
    assert started.status_code == 202, started.text
    first = wait_for_knockout(teacher, started.json()["id"])
    assert first["status"] == "finished" and first["seed"] == 7 and first["best_of"] == 3, first
    assert first["game"]["max_ticks"] == SHORT and first["rounds"] == 3

    # The draw is the seed's shuffle of the entries (in the order entered); the API does not hand out rules
    entries = room.tournament.entries()
    drawn = [place["entry_id"] for place in draw_entries(entries, 7)]
    assert [place["entry_id"] for place in first["draw"]] == drawn
    assert sorted(drawn) == sorted(e.id for e in entries) and all("text" not in p for p in first["draw"])

    ties = {(t["round"], t["tie"]): t for t in first["ties"]}
    assert sorted(ties) == [(1, 1), (1, 2), (1, 3), (1, 4), (2, 1), (2, 2), (3, 1)]
    byes = [t for t in first["ties"] if t["b"] is None]
    assert sorted(t["a"] for t in byes) == [1, 2, 3] and all(t["decided_by"] == "bye" and not t["matches"] for t in byes)

    game = GameConfig(**first["game"])
    rules = {place["draw"]: e.text for place in first["draw"] for e in entries if e.id == place["entry_id"]}
    for (round_number, tie_number), tie in ties.items():
        if round_number > 1:  # the winners of the two ties before meet
            assert (tie["a"], tie["b"]) == (ties[(round_number - 1, 2 * tie_number - 1)]["winner"],
                                            ties[(round_number - 1, 2 * tie_number)]["winner"])
        if tie["b"] is None:
            continue
        matches = tie["matches"]
        assert [m["seed"] for m in matches] == match_seeds(7, round_number, tie_number, 3)
        assert all(len(m["halves"]) == 2 for m in matches)  # mirrored: both halves, the sides swapped
        wins = [sum(m["winner"] == side for m in matches) for side in "AB"]
        goals = [sum(m["goals"][i] for m in matches) for i in (0, 1)]
        assert (tie["wins"], tie["goals"]) == (wins, goals)
        assert (tie["winner"], tie["decided_by"]) == tie_winner(tie["a"], tie["b"], wins, goals)
    # A tie's matches are the matches those two players play from those seeds, whatever else was played
    final = ties[(3, 1)]
    vocabulary = Vocabulary.default()
    again = play_matches(*(parse_rulebase(rules[final[side]], vocabulary) for side in "ab"),
                         [m["seed"] for m in final["matches"]], game, vocabulary)
    assert [list(m.goals) for m in again] == [m["goals"] for m in final["matches"]]
    names = {place["draw"]: place["name"] for place in first["draw"]}
    assert first["champion"] == names[final["winner"]]

    # The same seed: the same draw and the same matches; another seed draws otherwise
    second = wait_for_knockout(teacher, teacher.post("/api/class/knockouts", json={
        "best_of": 3, "seed": 7, "max_ticks": SHORT}).json()["id"])
    assert (second["draw"], second["ties"]) == (first["draw"], first["ties"])
    assert [p["entry_id"] for p in draw_entries(entries, 8)] != drawn


def test_pupils_read_the_bracket_but_cannot_start_one_and_bad_input_is_refused(room):
    teacher = room.teacher()
    ada = room.student("Ada")
    assert ada.post("/api/class/entries", json={"text": KICKER}).status_code == 201
    one = teacher.post("/api/class/knockouts", json={})
    assert one.status_code == 422 and "at least 2 entries" in one.json()["detail"]
    assert teacher.post("/api/class/entries", json={"text": DRIBBLER, "name": "Ben"}).status_code == 201

    refused = ada.post("/api/class/knockouts", json={"best_of": 1, "seed": 1, "max_ticks": SHORT})
    assert refused.status_code == 403 and "teacher" in refused.json()["detail"]
    for body, words in (({"best_of": 2}, "odd number"), ({"best_of": 11}, "best_of"), ({"best_of": 0}, "best_of"),
                        ({"seed": -1}, "seed"), ({"seed": "5"}, "seed"), ({"max_ticks": 10_001}, "max_ticks"),
                        ({"max_ticks": 1001}, "max_run_ticks"), ({"rounds": 3}, "rounds")):
        answer = teacher.post("/api/class/knockouts", json=body)
        assert answer.status_code == 422 and words in answer.text, (body, answer.text)
    assert room.store.list_knockouts() == []
    assert teacher.get("/api/class/knockouts/999").status_code == 404
    assert teacher.get("/api/class/knockouts/x").status_code == 422
    assert teacher.get("/api/class/knockouts/999/matches.csv").status_code == 404

    started = teacher.post("/api/class/knockouts", json={"best_of": 1, "max_ticks": SHORT})
    assert started.status_code == 202
    shown = started.json()
    assert 0 <= shown["seed"] and shown["status"] == "playing"  # a fresh seed, shown and recorded
    busy = teacher.post("/api/class/knockouts", json={"best_of": 1, "max_ticks": SHORT})
    assert busy.status_code == 409 and "being played" in busy.json()["detail"]
    done = wait_for_knockout(ada, shown["id"])
    assert done["status"] == "finished" and done["seed"] == shown["seed"]
    assert [k["id"] for k in ada.get("/api/class/knockouts").json()] == [shown["id"]]
    assert {p["name"] for p in done["draw"]} == {"Ada", "Ben"} and done["champion"] in {"Ada", "Ben"}


def test_a_knockout_survives_a_restart_and_one_left_playing_is_marked_interrupted(room, tmp_path):
    teacher = enter(room, 3)
    finished = wait_for_knockout(teacher, teacher.post("/api/class/knockouts", json={
        "best_of": 1, "seed": 3, "max_ticks": SHORT}).json()["id"])
    left_playing = room.store.create_knockout(4, 1, finished["game"], [{"draw": 1}, {"draw": 2}])

    room.store.close()
    reopened = Store(tmp_path / DATABASE_FILE)
    try:
        kept = reopened.get_knockout(finished["id"])
        assert kept.status == KnockoutStatus.FINISHED and kept.ties == finished["ties"]
        assert reopened.get_knockout(left_playing.id).status == KnockoutStatus.PLAYING
        restarted = Tournament(reopened, Vocabulary.default(), GameConfig(), lambda: room.classroom.settings)
        assert restarted.knockout.interrupted_at_start == [left_playing.id]
        assert reopened.get_knockout(left_playing.id).status == KnockoutStatus.INTERRUPTED
        assert reopened.get_knockout(finished["id"]).status == KnockoutStatus.FINISHED
    finally:
        reopened.close()
        room.store = Store(tmp_path / DATABASE_FILE)
        room.runs.store = room.store


def test_a_knockout_stops_when_the_app_ends_and_writes_nothing_after(room):
    """Found as a warning: a knockout's thread wrote to the store after it closed. Closing the tournament (as
    serve does before closing the store) stops a knockout after the tie being played, marked interrupted."""
    teacher = enter(room, 4)
    room.tournament.knockout.close(timeout=60)  # the app ends as the teacher presses Start
    started = teacher.post("/api/class/knockouts", json={"best_of": 1, "seed": 3, "max_ticks": SHORT})
    assert started.status_code == 202
    room.tournament.close(timeout=60)
    ended = room.store.get_knockout(started.json()["id"])
    assert ended.status == KnockoutStatus.INTERRUPTED and ended.ties == []
    assert not room.tournament.knockout.playing


def test_the_csv_has_one_row_per_match_and_names_a_spreadsheet_shows_as_text(room):
    teacher = enter(room, 3)
    knockout = wait_for_knockout(teacher, teacher.post("/api/class/knockouts", json={
        "best_of": 3, "seed": 5, "max_ticks": SHORT}).json()["id"])
    pupil = room.student("Zed")
    exported = pupil.get(knockout["csv"].replace(CLASS_URL, ""))
    assert exported.status_code == 200 and exported.headers["content-type"].startswith("text/csv")
    rows = list(csv.DictReader(io.StringIO(exported.text)))
    names = {p["draw"]: p["name"] for p in knockout["draw"]}
    expected = []
    for tie in knockout["ties"]:
        a, b = names[tie["a"]], names.get(tie["b"], "(bye)")
        for match in tie["matches"] or [None]:
            expected.append((str(tie["round"]), str(tie["tie"]), a, b,
                             "" if match is None else str(match["goals"][0]),
                             "" if match is None else str(match["seed"]), names[tie["winner"]]))
    shown = [(r["round"], r["tie"], r["player_a"], r["player_b"], r["goals_a"], r["seed"], r["tie_winner"])
             for r in rows]
    text = [tuple(cell.removeprefix("'") for cell in row) for row in shown]
    assert text == expected and len(rows) == 1 + 3 + 3  # a bye, the semi-final's 3 matches, the final's 3
    assert all(not r["player_a"].startswith("=") and not r["player_b"].startswith("=") for r in rows)
    assert any(r["player_a"] == "'" + FORMULA_NAME or r["player_b"] == "'" + FORMULA_NAME for r in rows)


def test_the_next_tie_waits_for_the_winners_of_the_two_before(room):
    """Round 2's tie is paired only once both ties feeding it are played (the bracket fills in tie by tie)."""
    enter(room, 4)
    record = room.store.create_knockout(1, 1, {}, draw_entries(room.tournament.entries(), 1))
    assert next_pairing(record) == (1, 1, 1, 4)
    room.store.record_tie(record.id, {"round": 1, "tie": 1, "a": 1, "b": 4, "matches": [], "winner": 4})
    assert next_pairing(room.store.get_knockout(record.id)) == (1, 2, 2, 3)
    room.store.record_tie(record.id, {"round": 1, "tie": 2, "a": 2, "b": 3, "matches": [], "winner": 2})
    assert next_pairing(room.store.get_knockout(record.id)) == (2, 1, 4, 2)
    room.store.record_tie(record.id, {"round": 2, "tie": 1, "a": 4, "b": 2, "matches": [], "winner": 2})
    assert next_pairing(room.store.get_knockout(record.id)) is None


def test_a_knockout_that_fails_says_why_and_lets_the_next_start(room, monkeypatch):
    """A knockout whose process cannot start ends failed, with the reason, for everyone listening; the next may
    start (it does not stay "being played")."""
    import soccer_lab.app.web.classroom.knockout as knockout_module

    def no_process(*_, **__):
        raise OSError("no process for you")

    monkeypatch.setattr(knockout_module, "ProcessPoolExecutor", no_process)
    teacher = enter(room, 2)
    heard = []
    room.tournament.add_listener(lambda event: heard.append(event.knockout.status))
    started = teacher.post("/api/class/knockouts", json={"best_of": 1, "seed": 2, "max_ticks": SHORT})
    failed = wait_for_knockout(teacher, started.json()["id"])
    assert failed["status"] == "failed" and "no process for you" in failed["error"] and failed["ties"] == []
    room.tournament.knockout.wait(10)
    assert heard == [KnockoutStatus.PLAYING, KnockoutStatus.FAILED]
    assert teacher.post("/api/class/knockouts", json={"best_of": 1, "max_ticks": SHORT}).status_code == 202


def test_a_class_of_thirty_sees_its_final_on_the_projector(room):
    """Found at 1280 x 800 with 30 entries: the projector's bracket had five rounds, the first one's 16 ties
    pushed the final off the screen. The projector shows the last three rounds and says where the others are."""
    from soccer_lab.app.web.ui.panels.knockout import PROJECTOR_ROUNDS, bracket_html

    draw = [{"draw": i, "name": f"Pupil {i}", "entry": i} for i in range(1, 31)]
    record = room.store.create_knockout(7, 1, GameConfig().model_dump(), draw)
    projected = bracket_html(record, 20, PROJECTOR_ROUNDS)
    assert [r for r in ("Round 1", "Round 2", "Quarter-finals", "Semi-finals", "Final") if f">{r}</div>" in projected] \
        == ["Quarter-finals", "Semi-finals", "Final"]
    assert "Round 1 to Round 2 (24 ties): in the Class tab and the CSV" in projected
    assert projected.count('class="knockout-tie"') == 4 + 2 + 1
    whole = bracket_html(record, 14)
    assert whole.count('class="knockout-tie"') == 16 + 8 + 4 + 2 + 1 and "knockout-earlier" not in whole
