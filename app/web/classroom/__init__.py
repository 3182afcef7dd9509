"""Classroom mode (`soccer-lab serve --class`): a class on the local network plays together.

- `admission.py`: the join code, the teacher token and the students' identities; every request and every
  UI websocket is admitted by `Classroom.admit` (docs/design.md, "Security" and "Classroom mode").
- `settings.py`: the class's settings the teacher may change (a student's run, a round's starts) and the
  fixed bounds (entry size, request rate).
- `rate.py`: each visitor's request rate.
- `tournament.py`: entries, rounds played as one GameBatch, their ranked tables and CSV.
- `knockout.py`: the class knockout: a seeded draw, ties of best-of-N matches, the bracket kept tie by tie, CSV.
- `qr.py`: the QR code of the class's address, drawn by the app (no outside service).
"""
