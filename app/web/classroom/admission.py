"""Who is in the class: the join code, the teacher token and each student's browser.

`serve --class` draws a join code (shown to the class) and a teacher token (the teacher's alone). A student
enters the code and a display name on the join page; the app answers with three HttpOnly, SameSite=Strict
cookies: the join code, and a token of their own that the store knows only by its SHA-256 (StudentRecord).
The teacher enters the token and gets a teacher cookie instead. Cookies belong to a host, not a port, so the
browser sends them to the app's port and to the UI's websocket port alike: `RequestGuard` (every HTTP
request) and `admit_only` (every websocket handshake) both ask `Classroom.admit`, which compares the code
and the teacher token in constant time (hmac.compare_digest). docs/design.md, "Classroom mode".
"""

from __future__ import annotations

import hashlib
import hmac
import secrets
import threading
from dataclasses import dataclass, field

from starlette.requests import cookie_parser

from soccer_lab.app.web.access import Visitor
from soccer_lab.app.web.classroom.names import NameRefused, display_name, skeleton
from soccer_lab.app.web.classroom.rate import RateLimiter
from soccer_lab.app.web.classroom.settings import (DISPLAY_NAME_MAX_LENGTH, MAX_STUDENTS, REQUEST_BURST,
                                                   REQUESTS_PER_SECOND, ClassSettings)
from soccer_lab.app.store import NotFound, Store, StoreError, StudentRecord, name_key, valid_name

JOIN_COOKIE = "soccer_lab_class"
STUDENT_COOKIE = "soccer_lab_student"
TEACHER_COOKIE = "soccer_lab_teacher"
COOKIE_MAX_AGE = 12 * 3600  # a school day: a browser closed and opened again stays in the class
CODE_ALPHABET = "ABCDEFGHJKMNPQRSTUVWXYZ23456789"  # no 0/O, 1/I/L: read off a projector
CODE_LENGTH = 6
WRONG_GUESS_COST = 10  # a wrong join code or teacher token costs ten requests: guessing is slow, joining is not
TEACHER_NAME = "teacher"


def new_join_code() -> str:
    return "".join(secrets.choice(CODE_ALPHABET) for _ in range(CODE_LENGTH))


def new_teacher_token() -> str:
    return secrets.token_urlsafe(18)


def token_hash(token: str) -> str:
    return hashlib.sha256(token.encode("utf-8", "replace")).hexdigest()


def same_secret(given: str | None, secret: str) -> bool:
    """`given` is `secret`, compared in constant time."""
    return hmac.compare_digest((given or "").encode("utf-8", "replace"), secret.encode("utf-8"))


class JoinRefused(ValueError):
    """A join or teacher attempt refused: the one line to show."""


class WrongSecret(JoinRefused):
    """A wrong join code or teacher token: a guess, charged WRONG_GUESS_COST of the visitor's rate."""


@dataclass
class Classroom:
    store: Store
    join_code: str
    teacher_token: str
    address: str  # the class's address as students open it: http://192.168.1.20:8000
    settings: ClassSettings = field(default_factory=ClassSettings)
    rate: RateLimiter = field(default_factory=lambda: RateLimiter(REQUESTS_PER_SECOND, REQUEST_BURST))
    _joining: threading.Lock = field(default_factory=threading.Lock)  # a name checked and taken in one step
    # Places joined since serve started whose cookie has not come back yet (a browser sends it with its next
    # page at once; a script that drops it never does), oldest first. Such a place has no entry and no run
    # (both need the cookie), so it gives way to a newcomer when the class is full or holds the name they ask.
    _unclaimed: dict[int, None] = field(default_factory=dict)

    def admit(self, cookie_header: str | None) -> Visitor | None:
        """The visitor whose browser sent these cookies, or None when it has not joined (no code, a wrong code,
        or a student this class does not know: removed, or from an earlier class)."""
        cookies = cookie_parser(cookie_header or "")
        if not same_secret(cookies.get(JOIN_COOKIE), self.join_code):
            return None
        if same_secret(cookies.get(TEACHER_COOKIE), self.teacher_token):
            return Visitor(None, TEACHER_NAME, teacher=True)
        token = cookies.get(STUDENT_COOKIE)
        student = self.store.student_by_token(token_hash(token)) if token else None
        if student is None:
            return None
        self._unclaimed.pop(student.id, None)
        return Visitor(student.id, student.name, teacher=False)

    def join(self, code: str, name: str, cookie_header: str | None) -> tuple[StudentRecord, dict[str, str]]:
        """A student joins under `name`: their record and the cookies to set. A browser holds one place: one
        that already joined (its student cookie) keeps its place and identity, renamed when the name differs,
        so one pupil is one account (`owner` of their runs) whatever names they try."""
        if not same_secret(code.strip().upper(), self.join_code):
            raise WrongSecret("that is not this class's join code: check it on the teacher's screen")
        name = valid_display_name(name)
        token = cookie_parser(cookie_header or "").get(STUDENT_COOKIE)
        with self._joining:
            known = self.store.student_by_token(token_hash(token)) if token else None
            self._check_unlike_others(name, known)
            if known is not None:
                if name_key(known.name) != name_key(name) or known.name != name:
                    known = self._renamed(known, name)
                return known, {JOIN_COOKIE: self.join_code, STUDENT_COOKIE: token}
            if len(self.store.list_students()) >= MAX_STUDENTS and not self._give_way():
                raise JoinRefused(f"the class has {MAX_STUDENTS} students, its limit: the teacher may remove some")
            token = secrets.token_urlsafe(32)
            try:
                student = self.store.add_student(name, token_hash(token))
            except StoreError as exc:
                raise JoinRefused(str(exc)) from None
            self._unclaimed[student.id] = None
        return student, {JOIN_COOKIE: self.join_code, STUDENT_COOKIE: token}

    def _check_unlike_others(self, name: str, own: StudentRecord | None) -> None:
        """JoinRefused when `name` looks like another student's (their confusable skeletons are equal); an
        unclaimed place holding it gives way."""
        look = skeleton(name)
        for student in self.store.list_students():
            if (own is None or student.id != own.id) and (skeleton(student.name) == look
                                                         or name_key(student.name) == name_key(name)):
                if student.id in self._unclaimed:
                    self._remove_unclaimed(student.id)
                    continue
                raise JoinRefused(f"the name {name!r} is taken in this class, or looks like {student.name!r}: "
                                  "choose another")

    def _give_way(self) -> bool:
        """Free the oldest unclaimed place; False when there is none."""
        while self._unclaimed:
            if self._remove_unclaimed(next(iter(self._unclaimed))):
                return True
        return False

    def _remove_unclaimed(self, student_id: int) -> bool:
        """False when the place was gone already (the teacher removed it)."""
        del self._unclaimed[student_id]
        try:
            self.store.remove_student(student_id)
        except NotFound:
            return False
        return True

    def _renamed(self, student: StudentRecord, name: str) -> StudentRecord:
        try:
            return self.store.rename_student(student.id, name)
        except StoreError as exc:
            raise JoinRefused(str(exc)) from None

    def teacher_login(self, token: str) -> dict[str, str]:
        if not same_secret(token.strip(), self.teacher_token):
            raise WrongSecret("that is not the teacher token `soccer-lab serve --class` printed")
        return {JOIN_COOKIE: self.join_code, TEACHER_COOKIE: self.teacher_token}


def valid_display_name(name: object) -> str:
    """A display name: one line of plain text (the store's rule for names), NFKC-normalised, nothing invisible
    or misleading in it (app/web/classroom/names.py), at most DISPLAY_NAME_MAX_LENGTH; not the teacher's, nor
    one that looks like it."""
    try:
        name = valid_name(name)  # the store's own check, so the message is the same everywhere
        name = display_name(name)
    except (StoreError, NameRefused) as exc:
        raise JoinRefused(str(exc)) from None
    if len(name) > DISPLAY_NAME_MAX_LENGTH:
        raise JoinRefused(f"a display name is at most {DISPLAY_NAME_MAX_LENGTH} characters")
    if name_key(name) == TEACHER_NAME or skeleton(name) == skeleton(TEACHER_NAME):
        raise JoinRefused("choose another name ('teacher' is the teacher's)")
    return name


def set_cookie_headers(cookies: dict[str, str]) -> list[str]:
    """Set-Cookie values: HttpOnly (no script reads them), SameSite=Strict (no other site's page sends them)."""
    return [f"{name}={value}; Path=/; Max-Age={COOKIE_MAX_AGE}; HttpOnly; SameSite=Strict"
            for name, value in cookies.items()]
